#!/bin/sh
# One-shot `cmr region` wall time per backend (issue 39's target: Vulkan at
# most 3x the CPU backend at 512x512, the pipeline cache warm). Runs the two
# backends in turn ROUNDS times (interleaved, so load falls on both alike)
# after one warm-up run each (which fills the cache directory), and prints
# the best and median milliseconds of each and their ratio, and those of
# `cmr --version` (the start-up every command pays).
# Run from the repository root:
#   VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json tools/bench/oneshot_region.sh [ROUNDS] [CMR]
set -eu
ROUNDS=${1:-15}
CMR=${2:-build/tools/cmr}
ARGS="region examples/figures/fig2.json --point 1 --depth 10 --size 512x512"
ms() {  # wall milliseconds of one run (version: cmr --version)
  t0=$(date +%s%N)
  if [ "$1" = version ]; then "$CMR" --version >/dev/null 2>&1; else "$CMR" $ARGS --backend "$1" >/dev/null 2>&1; fi
  t1=$(date +%s%N)
  echo $(( (t1 - t0) / 1000000 ))
}
ms cpu >/dev/null
ms vulkan >/dev/null
: >/tmp/oneshot_cpu.$$
: >/tmp/oneshot_vulkan.$$
: >/tmp/oneshot_version.$$
i=0
while [ $i -lt "$ROUNDS" ]; do
  ms cpu >>/tmp/oneshot_cpu.$$
  ms vulkan >>/tmp/oneshot_vulkan.$$
  ms version >>/tmp/oneshot_version.$$
  i=$((i + 1))
done
stats() { sort -n "$1" | awk '{a[NR]=$1} END {printf "%d %d", a[1], a[int((NR+1)/2)]}'; }
set -- $(stats /tmp/oneshot_cpu.$$) $(stats /tmp/oneshot_vulkan.$$) $(stats /tmp/oneshot_version.$$)
rm -f /tmp/oneshot_cpu.$$ /tmp/oneshot_vulkan.$$ /tmp/oneshot_version.$$
echo "one-shot cmr $ARGS ($ROUNDS rounds, $(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg))"
echo "  --backend cpu:    best $1 ms, median $2 ms"
echo "  --backend vulkan: best $3 ms, median $4 ms ($(awk "BEGIN {printf \"%.1f\", $3 / $1}")x the CPU's best, $(awk "BEGIN {printf \"%.1f\", $4 / $2}")x its median)"
echo "  cmr --version:    best $5 ms, median $6 ms"
