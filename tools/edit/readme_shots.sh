#!/bin/sh
# The README's screenshots of cmr edit (docs/img/edit*.png), taken from the
# real window under Xvfb by scripts, and its --bench numbers.
#   tools/edit/readme_shots.sh [BUILD_DIR [--no-bench]]     (default: build)
set -eu
build=${1:-build}
cmr="$build/tools/cmr"
src=$(cd "$(dirname "$0")/../.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
run() { xvfb-run -a -s "-screen 0 1280x1024x24" "$cmr" "$@"; }

# 1. The Fig. 8 spline, P3's region, the comb, the panels.
printf 'select 3\nwait 2\n' >"$tmp/fig8.txt"
run edit "$src/examples/figures/fig8.json" --size 1024x768 --script "$tmp/fig8.txt" \
  --screenshot "$src/docs/img/edit.png"

# 2. kappa-curve mode: six clicks (Fig. 13's closed blob), modify, a handle's
#    region in its cubic piece after moving it within the region.
cat >"$tmp/kappa.txt" <<'SCRIPT'
view -1.5 -5 10.5 4
kcurve points
closed on
mouse 128 341
press left
release left
mouse 384 384
press left
release left
mouse 555 256
press left
release left
mouse 469 68
press left
release left
mouse 256 43
press left
release left
mouse 85 171
press left
release left
kcurve modify
select 16
view 3.6 -0.4 7.6 2.6
wait 2
SCRIPT
run edit --size 1024x768 --script "$tmp/kappa.txt" --screenshot "$src/docs/img/edit_kcurve.png"

# 3. fix: P2 selected outside its region, then the nearest certified fix
#    (bezierize/fix) moved it onto the region's edge; the status line says so.
printf 'select 2\nfix\nwait 2\n' >"$tmp/fix.txt"
run edit "$src/examples/figures/fig8.json" --size 1024x768 --script "$tmp/fix.txt" \
  --screenshot "$src/docs/img/edit_fix.png"

# 4. The benchmark (prints the machine and the load average).
[ "${2:-}" = --no-bench ] || run edit --bench
