#!/usr/bin/env bash
# Regenerates docs/img/fix.png (docs/fix.md) with the command the page shows,
# and prints its JSON. Run from the repository root after building (build/tools/cmr).
set -euo pipefail
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
build/tools/cmr fix examples/figures/fig8.json --require cmrwi --out "$out/fig8_fixed.json" \
  --png docs/img/fix.png --pretty
