#!/usr/bin/env bash
# An installed cmr stands alone: `cmake --install` into a fresh prefix copies
# bin/cmr and nothing else, the binary names neither the source tree nor the
# example files, and run from an empty folder (no source tree in reach, only
# a spline given by path) it draws the figures, analyses and renders regions.
# Usage: installed_test.sh CMAKE BUILD_DIR SOURCE_DIR
set -euo pipefail
cmake_cmd=$1 build=$2 source=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "installed_test: $*" >&2; exit 1; }

"$cmake_cmd" --install "$build" --prefix "$tmp/prefix" >/dev/null
files=$(cd "$tmp/prefix" && find . -type f | sort)
[[ $files == "./bin/cmr" ]] || fail "the install holds more than bin/cmr: $files"
cmr=$tmp/prefix/bin/cmr
n=$(grep -c -F "$source" "$cmr" || true)
[[ $n == 0 ]] || fail "bin/cmr names the source tree $source ($n times)"
n=$(grep -c -F "examples/figures" "$cmr" || true)
[[ $n == 0 ]] || fail "bin/cmr names examples/figures ($n times): it would read the source tree"

# The spline travels by path, copied out of the tree; the run starts in an
# empty folder with a bare environment.
mkdir "$tmp/empty" "$tmp/data"
cp "$source/examples/figures/fig8.json" "$tmp/data/s.json"
cd "$tmp/empty"
run() { env -i PATH=/usr/bin:/bin HOME="$tmp/empty" "$cmr" "$@"; }

run figures --out "$tmp/figs" --size 64 --backend cpu >"$tmp/figures.txt" || fail "cmr figures failed: $(tail -3 "$tmp/figures.txt")"
[[ -s $tmp/figs/index.html ]] || fail "cmr figures wrote no index.html"
ls "$tmp/figs"/*.png >/dev/null 2>&1 || fail "cmr figures wrote no PNG"

run analyze "$tmp/data/s.json" >"$tmp/analyze.json" || fail "cmr analyze failed"
grep -q '"cmrwi"' "$tmp/analyze.json" || fail "cmr analyze printed no verdict: $(cat "$tmp/analyze.json")"

run region "$tmp/data/s.json" --point 3 --size 32x32 --backend cpu --png "$tmp/r.png" --labels "$tmp/r.pgm" \
  >"$tmp/region.json" || fail "cmr region failed"
grep -q '"points"' "$tmp/region.json" || fail "cmr region printed no summary"
[[ -s $tmp/r.png && -s $tmp/r.pgm ]] || fail "cmr region wrote no picture or label map"

[[ -z $(ls -A "$tmp/empty") ]] || fail "a command wrote into the working folder: $(ls -A "$tmp/empty")"
echo "installed cmr stands alone"
