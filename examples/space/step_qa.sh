#!/usr/bin/env bash
# QA of a CAD model (docs/space.md): writes the small OpenCASCADE model
# (tools/step_model.cpp) as STEP, imports every B-spline/Bezier edge with
# `cmr import`, and judges them all with `cmr report` (space curves: certified
# curvature monotonicity, zero curvature, extrema, joints).
#   bash examples/space/step_qa.sh [BUILD_DIR [OUT_DIR]]   (default build, step_qa)
# Needs a build with the STEP importer (OpenCASCADE; tools/setup.sh).
# Exit: 0 when the report was written (the report's own status is printed:
# 1 some curve's curvature is not monotone, 2 some curve could not be judged),
# 2 when
# the model or the import failed, 77 when cmr was built without STEP support.
set -euo pipefail
build=${1:-build}
out=${2:-step_qa}
if [[ ! -x $build/tools/cmr_step_model ]]; then
  echo "step_qa: $build/tools/cmr_step_model is missing (cmr was built without STEP support)" >&2
  exit 77
fi
mkdir -p "$out"
"$build/tools/cmr_step_model" "$out/model.step"
"$build/tools/cmr" import "$out/model.step" --out "$out/curves"
status=0
# --no-thumbnails: the region thumbnails (one per control point) of the
# model's degree-14 edges (lambda3 of degree 73 per pixel) would take far
# longer than the QA itself (docs/space.md).
"$build/tools/cmr" report "$out"/curves/*.json --out "$out/report" --no-thumbnails || status=$?
echo "step_qa: cmr report exited $status; open $out/report/index.html"
[[ -f $out/report/report.json ]] || exit 2
