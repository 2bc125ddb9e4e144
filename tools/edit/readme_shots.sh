#!/bin/sh
# The README's screenshots of cmr edit (docs/img/edit*.png), taken from the
# real window under Xvfb by scripts, and its --bench numbers.
#   tools/edit/readme_shots.sh [BUILD_DIR [--no-bench]]     (default: build)
set -eu
build=${1:-build}
cmr=$(cd "$build" && pwd)/tools/cmr
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

# 4. The legend (issue 21): every point's region overlapped, each outlined in
#    its point's hue, the pointer over a pixel naming the regions that hold it.
printf 'all on\nmouse 480 300\nwait 3\n' >"$tmp/legend.txt"
run edit "$src/examples/figures/fig8.json" --size 1024x768 --script "$tmp/legend.txt" \
  --screenshot "$src/docs/img/edit_legend.png"

# 5. The curvature graph with values: log10 |kappa| (Fig. 8's dip between its
#    flattest and sharpest points), the pointer's read-out, the segment table.
printf 'select 3\ngraph log\nmouse 320 700\nwait 3\n' >"$tmp/graph.txt"
run edit "$src/examples/figures/fig8.json" --size 1024x768 --script "$tmp/graph.txt" \
  --screenshot "$src/docs/img/edit_graph.png"

# 6. A glyph being edited: both contours of DejaVu Sans's O with the node
#    names of cmr import and the report, the outer one's comb fitted.
font=/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf
if [ -f "$font" ]; then
  printf 'contour 1\nselect 3\nfit\nwait 2\n' >"$tmp/glyph.txt"
  (cd "$tmp" && run edit "$font" --glyph O --size 1280x900 --script "$tmp/glyph.txt" \
    --screenshot "$src/docs/img/edit_glyph.png")
fi

# 6b. A UFO source's glyph (examples/ufo/Sans.ufo, DejaVu Sans's O as a UFO
#     3): short point names, the comb of every contour, the legend docked in
#     the panel; a point dragged onto the grid (the copy is saved, not the
#     example).
cp -r "$src/examples/ufo/Sans.ufo" "$tmp/Sans.ufo"
printf 'comb-all on
select 3
drag 3 250 330
save
mouse 5 5
wait 2
' >"$tmp/ufo.txt"
(cd "$tmp" && run edit Sans.ufo --glyph O --size 1280x900 --script "$tmp/ufo.txt" \
  --screenshot "$src/docs/img/edit_ufo.png")

# 7. The benchmark (prints the machine and the load average).
[ "${2:-}" = --no-bench ] || run edit --bench
