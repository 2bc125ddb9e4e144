#!/usr/bin/env bash
# QA of a CAD model (docs/space.md): writes the small OpenCASCADE model
# (tools/step_model.cpp) as STEP, imports every B-spline/Bezier edge with
# `cmr import` (each curve named by its STEP entity, #id), and judges them
# all with `cmr report` (space curves: certified curvature monotonicity, zero
# curvature, extrema, joints). Then the class-A-style wire (`cmr_step_model
# OUT wire`): one chain of four edges, its junctions judged G1/G2/G3. Then
# a chain fix (`cmr_step_model OUT spiral-dent`): a spiral chain of two edges
# with a dent in the first, repaired with `cmr fix --chain 1 --keep g2`.
#   bash examples/space/step_qa.sh [BUILD_DIR [OUT_DIR]]
# BUILD_DIR defaults to build; OUT_DIR to $TMPDIR/cmr_step_qa (/tmp when
# TMPDIR is unset): outside the repository, as it is rewritten on each run.
# Writes OUT_DIR/model.step, curves/, report/ (index.html, report.json),
# report.txt (cmr report's summary), report_cad/ and report_cad.txt (the
# same edges gated: --require cmrwi --constant-tol 1e-6), wire.step,
# wire_curves/ and chains.txt
# (cmr import's chain report), spiral-dent.step, chain_fix.json (cmr fix's
# document) and chain_fixed/ (the chain's edges, fixed).
# Needs a build with the STEP importer (OpenCASCADE; tools/setup.sh).
# Exit: 0 when both reports were written. The last line says how many curves
# pass: `cmr report` without --require gates nothing and exits 0 even when
# curves fail (with --require cmrwi it would exit 1). 2 when the model, the
# import or the report failed; 77 when cmr was built without STEP support.
set -euo pipefail
build=${1:-build}
out=${2:-${TMPDIR:-/tmp}/cmr_step_qa}
if [[ ! -x $build/tools/cmr_step_model ]]; then
  echo "step_qa: $build/tools/cmr_step_model is missing (cmr was built without STEP support)" >&2
  exit 77
fi
mkdir -p "$out"
"$build/tools/cmr_step_model" "$out/model.step"
"$build/tools/cmr" import "$out/model.step" --out "$out/curves"
# --no-thumbnails: the region thumbnails (one per control point) of the
# model's degree-14 edges (lambda3 of degree 73 per pixel) would take far
# longer than the QA itself (docs/space.md).
"$build/tools/cmr" report "$out"/curves/*.json --out "$out/report" --no-thumbnails >"$out/report.txt" || exit 2
cat "$out/report.txt"
[[ -f $out/report/report.json ]] || exit 2
# As a CAD run gates: |kappa| monotone, or an arc of constant curvature
# within 1e-6 radians of turning (docs/space.md, Tolerances): the model's
# circles, OpenCASCADE's degree-14 approximations among them, pass; exit 1
# (the designed curves that fail) is expected.
rc=0
"$build/tools/cmr" report "$out"/curves/*.json --out "$out/report_cad" --no-thumbnails --require cmrwi \
  --constant-tol 1e-6 >"$out/report_cad.txt" || rc=$?
[[ $rc -le 1 && -f $out/report_cad/report.json ]] || exit 2
echo "with --require cmrwi --constant-tol 1e-6: $(cat "$out/report_cad.txt")"
# The class-A-style wire: its chain report.
"$build/tools/cmr_step_model" "$out/wire.step" wire
"$build/tools/cmr" import "$out/wire.step" --out "$out/wire_curves" >"$out/chains.txt"
cat "$out/chains.txt"
# A chain fix: the dented spiral's first edge repaired, every edge's ends
# (position, tangent, curvature vector) held, so its G3 junction stays G3.
"$build/tools/cmr_step_model" "$out/spiral-dent.step" spiral-dent
"$build/tools/cmr" fix "$out/spiral-dent.step" --chain 1 --keep g2 --out "$out/chain_fixed" --pretty >"$out/chain_fix.json" || exit 2
python3 -c 'import json, sys; d = json.load(open(sys.argv[1])); print("chain fix:", d["before"], "->", d["after"].split(": ", 2)[2])' \
  "$out/chain_fix.json"
# "10 space curves: 2 pass, 8 fail, 0 invalid; wrote ..." -> "10 curves: 2 pass, 8 fail, 0 invalid"
verdict=$(sed -n 's/^\([0-9]*\) space curves*: \([^;]*\);.*/\1 curves: \2/p' "$out/report.txt")
echo "step_qa: ${verdict:-see $out/report.txt} (no gate: cmr report exits 0); open $out/report/index.html; chains: $out/chains.txt"
