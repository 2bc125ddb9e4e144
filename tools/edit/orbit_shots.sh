#!/usr/bin/env bash
# The orbit view's screenshot in docs/edit.md and its --bench numbers:
#   tools/edit/orbit_shots.sh [BUILD]
# (lavapipe under Xvfb, as tools/edit/readme_shots.sh does for the planar editor).
set -eu
build=${1:-build}
cmr=$(cd "$build" && pwd)/tools/cmr
src=$(cd "$(dirname "$0")/../.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export VK_DRIVER_FILES=${VK_DRIVER_FILES:-/usr/share/vulkan/icd.d/lvp_icd.x86_64.json}
# A screen larger than the window: X's own cursor (at the screen's centre) stays off the window.
run() { xvfb-run -a -s "-screen 0 2048x1600x24" "$cmr" "$@"; }

printf 'orbit 70 50\ndrag 2 0.3 -0.2 8\nwait 2\n' >"$tmp/orbit.txt"
run edit "$src/examples/space/fig8_lifted.json" --point 2 --size 1024x768 --script "$tmp/orbit.txt" \
  --screenshot "$src/docs/img/edit_orbit.png"

run edit --bench "$src/examples/space/fig8b_lifted.json" --point 3 --size 1024x768
