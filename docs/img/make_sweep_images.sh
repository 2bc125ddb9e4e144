#!/usr/bin/env bash
# Regenerates the README pictures of "cmr region --contours" and "cmr sweep"
# (docs/img/contours.png, sweep_*.png) from the commands the README shows.
# Run from the repository root after building (build/tools/cmr); needs
# chromium (tools/setup.sh) to turn SVG/HTML into PNG.
set -euo pipefail
cmr=build/tools/cmr
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
shot() {  # shot PAGE OUT.png WIDTH HEIGHT
  chromium --headless --no-sandbox --disable-gpu --hide-scrollbars --window-size="$3,$4" \
    --screenshot="$2" "file://$1" >/dev/null 2>&1
}

# Contours: a 40x40 label map against its refined outlines.
$cmr region examples/figures/fig8.json --point 3 --backend cpu --size 40x40 --view -0.1,-5.4,3.0,-2.3 \
  --png "$tmp/c.png" --contours "$tmp/c.svg" >/dev/null
cat >"$tmp/c.html" <<HTML
<html><body style="margin:0;font-family:DejaVu Sans;font-size:14px">
<table><tr><td><img src="c.png" width="380" style="image-rendering:pixelated"></td>
<td><img src="c.svg" width="380" height="380"></td></tr>
<tr><td>label map, 40x40 pixels (--png)</td><td>--contours c.svg: vertices bisected onto the exact boundary</td></tr></table>
</body></html>
HTML
shot "$tmp/c.html" docs/img/contours.png 780 420

# The two knot experiments (README "cmr sweep").
mkdir -p out/sweep-knot out/sweep-clamp
$cmr sweep examples/figures/fig8.json --point 3 --knot 3 --from 2.1 --to 3.9 --steps 36 \
  --size 160x160 --view -0.1,-5.4,3.0,-2.3 --out-dir out/sweep-knot >/dev/null
$cmr sweep examples/sweep/fig9_uniform.json --point 3 --to-knots 0,0,0,1,2,3,3,3 --steps 24 \
  --size 160x160 --view 2.8,-2.9,4.3,-1.4 --out-dir out/sweep-clamp >/dev/null
cp out/sweep-knot/area.png docs/img/sweep_knot_area.png
cp out/sweep-clamp/area.png docs/img/sweep_clamp_area.png
strip() {  # strip DIR OUT.png STEP...
  local dir=$1 out=$2
  shift 2
  local cells="" n=0
  for s in "$@"; do
    local f
    f=$(printf 'step_%03d' "$s")
    local v
    v=$(sed -n "$((s + 1))p" "$dir/steps.jsonl" | python3 -c 'import json,sys; print("%.3g" % json.load(sys.stdin)["value"])')
    cells+="<td><img src=\"$PWD/$dir/frames/$f.png\" width=160><br>$v</td>"
    n=$((n + 1))
  done
  echo "<html><body style=\"margin:0;font-family:DejaVu Sans;font-size:13px;text-align:center\"><table><tr>$cells</tr></table></body></html>" >"$tmp/strip.html"
  shot "$tmp/strip.html" "$out" $((n * 166 + 8)) 200
}
strip out/sweep-knot docs/img/sweep_knot_frames.png 0 6 12 18 24 30
strip out/sweep-clamp docs/img/sweep_clamp_frames.png 0 6 12 18 24
python3 docs/img/tube_svg.py out/sweep-knot/tube.obj "$tmp/t1.svg" "fig8 P3, knot 3 from 2.1 to 3.9 (upwards)"
shot "$tmp/t1.svg" docs/img/sweep_knot_tube.png 640 640
python3 docs/img/tube_svg.py out/sweep-clamp/tube.obj "$tmp/t2.svg" "fig9 P3, uniform (bottom) to clamped (top)"
shot "$tmp/t2.svg" docs/img/sweep_clamp_tube.png 640 640
echo "docs/img: contours.png sweep_{knot,clamp}_{area,frames,tube}.png"
