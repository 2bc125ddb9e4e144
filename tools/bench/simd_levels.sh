#!/bin/sh
# cmr's CPU region render at each SIMD level (issue 23, item 2; docs/performance.md):
# bench_region in cmr-only mode, interleaved rounds so that a shared, loaded
# machine's load falls on every column alike, and per cell the median over
# rounds of the CPU ms that bench_region reports (best of REPS per run).
#
# Usage (from the repository root, after building bench_region):
#   tools/bench/simd_levels.sh ROUNDS REPS FILTER [BEFORE_BINARY]
# FILTER is bench_region's cell filter ("scene view D size" text, e.g.
# "whole region 10 512"; "" for every cell). BEFORE_BINARY, if given, is a
# bench_region built from another commit (e.g. before the SIMD levels), run
# first in each round. Columns: before (if given), CMR_SIMD=scalar, sse2, avx2
# (the levels this CPU has), and the default (unset).
set -eu
if [ $# -lt 3 ]; then
  echo "usage: tools/bench/simd_levels.sh ROUNDS REPS FILTER [BEFORE_BINARY]" >&2
  exit 2
fi
rounds=$1 reps=$2 filter=$3 before=${4:-}
bench=build/tools/bench/bench_region
for b in "$bench" ${before:+"$before"}; do
  if [ ! -x "$b" ]; then
    echo "simd_levels.sh: $b is not an executable bench_region" >&2
    exit 2
  fi
done
: "${VK_DRIVER_FILES:=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json}"
export VK_DRIVER_FILES
levels="scalar sse2"
grep -qw avx2 /proc/cpuinfo 2>/dev/null && levels="$levels avx2"
out=$(mktemp)
trap 'rm -f "$out"' EXIT
load_before=$(cut -d' ' -f1 /proc/loadavg 2>/dev/null || echo ?)
r=0
while [ "$r" -lt "$rounds" ]; do
  if [ -n "$before" ]; then
    "$before" "$reps" "$filter" cmr 2>/dev/null | grep "cmr CPU" | sed 's/^/before|/' >>"$out"
  fi
  for l in $levels; do
    CMR_SIMD=$l "$bench" "$reps" "$filter" cmr 2>/dev/null | grep "cmr CPU" | sed "s/^/$l|/" >>"$out"
  done
  env -u CMR_SIMD "$bench" "$reps" "$filter" cmr 2>/dev/null | grep "cmr CPU" | sed 's/^/default|/' >>"$out"
  r=$((r + 1))
done
echo "1-minute load average: $load_before before, $(cut -d' ' -f1 /proc/loadavg 2>/dev/null || echo ?) after"
python3 - "$out" ${before:+before} $levels default <<'EOF'
import re, statistics, sys
rows, cols = {}, sys.argv[2:]
for line in open(sys.argv[1]):
    col, rest = line.split("|", 1)
    m = re.match(r"\s*(.*?)\s+cmr CPU\s+([\d.]+) ms wall\s+([\d.]+) ms CPU", rest)
    if m:
        rows.setdefault(re.sub(r"\s+", " ", m.group(1)), {}).setdefault(col, []).append(float(m.group(3)))
print("CPU ms per render (median over rounds of bench_region's best of reps)")
print("%-44s" % "cell" + "".join("%10s" % c for c in cols))
for cell, by in rows.items():
    print("%-44s" % cell + "".join("%10.3f" % statistics.median(by[c]) if c in by else "%10s" % "-" for c in cols))
EOF
