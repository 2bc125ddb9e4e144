#!/usr/bin/env bash
# Regenerates docs/img/space_step_report.png (README, docs/space.md): the
# report of the STEP QA example (examples/space/step_qa.sh), the top of its
# index.html in chromium. Run from the repository root after building with
# the STEP importer (build/tools/cmr, build/tools/cmr_step_model).
set -euo pipefail
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bash examples/space/step_qa.sh build "$tmp/qa"
chromium --headless --no-sandbox --disable-gpu --hide-scrollbars --window-size=1000,1100 \
  --screenshot=docs/img/space_step_report.png "file://$tmp/qa/report/index.html" >/dev/null 2>&1
