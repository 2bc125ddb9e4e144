#!/usr/bin/env bash
# Regenerates the README pictures of "cmr region --weight" (docs/img/weight_region.png, weight_pole.png)
# with the command the README shows, and prints its JSON (the intervals the
# README quotes). Run from the repository root after building (build/tools/cmr).
set -euo pipefail
build/tools/cmr region examples/figures/fig8.json --weight 2 --from 0.2 --to 3 \
  --plot docs/img/weight_region.png --pretty
# The time the README quotes, and the machine.
echo "machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p')"
TIMEFORMAT='wall %R s'
time build/tools/cmr region examples/figures/fig8.json --weight 2 --from 0.2 --to 3 >/dev/null
# The pole picture: the quarter circle's middle weight through zero.
build/tools/cmr region examples/rational/quarter_circle.json --weight 1 --from -3 --to 2 \
  --plot docs/img/weight_pole.png --pretty
