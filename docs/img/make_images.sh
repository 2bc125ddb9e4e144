#!/usr/bin/env bash
# Regenerates every picture in docs/img that a cmr command draws, with the
# commands the docs show (the editor screenshots edit*.png are made by
# tools/edit/readme_shots.sh). Run from the repository root after building.
#
#   docs/img/make_images.sh            rewrites docs/img/*.png
#   docs/img/make_images.sh --direct OUT
#                                      writes only the pictures cmr writes
#                                      byte for byte (no chromium) into OUT;
#                                      the docs_images_current test compares
#                                      them with the committed ones.
#
# CMR (default build/tools/cmr) names the binary.
set -euo pipefail
cmr=${CMR:-build/tools/cmr}
out=docs/img
direct_only=0
if [[ ${1:-} == --direct ]]; then
  direct_only=1
  out=$2
  mkdir -p "$out"
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# docs/analyze.md, "Segments and joints": where P3 may go so that the wave
# keeps a maximum at joint 2, a minimum at joint 3 and no other extremum.
$cmr region examples/wave.json --point 3 --split 2,3 --view=-0.5,-2.6,6.7,2.8 --size 480x360 \
  --png "$out/segments.png" >/dev/null 2>"$tmp/err" || { cat "$tmp/err" >&2; exit 1; }

# docs/region.md, "The region of a weight" (make_weight_image.sh prints the
# JSON and the time the page quotes as well).
$cmr region examples/figures/fig8.json --weight 2 --from 0.2 --to 3 --plot "$out/weight_region.png" >/dev/null
$cmr region examples/rational/quarter_circle.json --weight 1 --from -3 --to 2 --plot "$out/weight_pole.png" >/dev/null

# README: three of the paper's figures as `cmr figures` draws them.
$cmr figures --out "$tmp/figures" >/dev/null 2>"$tmp/err" || { cat "$tmp/err" >&2; exit 1; }
for f in fig2 fig8 fig10; do cp "$tmp/figures/$f.png" "$out/$f.png"; done

if [[ $direct_only == 1 ]]; then
  exit 0
fi
# The pictures composed in chromium from cmr's outputs (contours, sweeps).
bash docs/img/make_sweep_images.sh
echo "docs/img: segments.png weight_region.png weight_pole.png fig2.png fig8.png fig10.png (and the sweep pictures above)"
