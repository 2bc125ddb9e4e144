#!/usr/bin/env bash
# Regenerates docs/space.md's picture (docs/img/space_region.png) and prints
# the outputs the page quotes: `cmr analyze --torsion` of a space curve and the
# region summary. Run from the repository root after building (build/tools/cmr).
set -euo pipefail
build/tools/cmr analyze examples/space/fig8b_lifted.json --torsion --pretty
build/tools/cmr region examples/space/fig8b_lifted.json --point 3 --plane xy \
  --view -1.2,-1.2,0.8,0.8 --size 320x320 --backend cpu --png docs/img/space_region.png --stats --pretty
