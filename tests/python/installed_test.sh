#!/usr/bin/env bash
# `cmake --install BUILD --component python --prefix P` gives a package that
# imports from P alone: run from an empty folder with only P's site folder on
# the path, it analyses a copy of Fig. 8 (cmrwi "none", as cmr analyze says).
# Usage: installed_test.sh CMAKE BUILD_DIR PYTHON SITE_DIR_IN_PREFIX FIG8_JSON
set -euo pipefail
cmake_cmd=$1 build=$2 python=$3 site=$4 fig8=$5
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$cmake_cmd" --install "$build" --component python --prefix "$tmp/prefix" >/dev/null
files=$(cd "$tmp/prefix/$site/cmr" && ls | sort | tr '\n' ' ')
echo "installed: $files"
[[ $files == *"__init__.py"* && $files == *"_cmr."*".so"* && $files == *"pen.py"* ]] || { echo "missing files" >&2; exit 1; }
cp "$fig8" "$tmp/fig8.json"
mkdir "$tmp/empty"
cd "$tmp/empty"
out=$(env -u PYTHONPATH PYTHONPATH="$tmp/prefix/$site" PYTHONDONTWRITEBYTECODE=1 "$python" -c "
import cmr
assert cmr.__file__.startswith('$tmp/prefix/'), cmr.__file__
print(cmr.analyze('$tmp/fig8.json')['spline']['cmrwi'])")
[[ $out == none ]] || { echo "unexpected verdict: $out" >&2; exit 1; }
echo "ok: $out"
