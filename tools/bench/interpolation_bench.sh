#!/bin/bash
# Speed of the interpolation gates (issue 37, Speed; docs/interpolation.md):
# on a variable font's Latin letters and on all its glyphs, the midway
# baseline (tools/bench/midway_kinks.py), `cmr report` with each
# interpolation gate on 2 threads (wall time and peak memory), and
# bench_between (the curvature certificate alone: the share of cells decided
# by the floating-point bound and by the exact path).
#   tools/bench/interpolation_bench.sh [BUILD_DIR] [FONT]
# Defaults: build, Inter roman (Debian fonts-inter-variable). Timings only:
# nothing is asserted. cmr report exits 2 when the reader refuses a glyph
# (printed with its reason).
set -u
build=${1:-build}
font=${2:-/usr/share/fonts/truetype/inter-vf/Inter-roman.var.ttf}
here=$(cd "$(dirname "$0")" && pwd)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'); $(uptime | sed 's/.*load/load/')"
echo "font: $font"
for glyphs in A-Z,a-z all; do
  echo "== glyphs $glyphs"
  /usr/bin/python3 "$here/midway_kinks.py" "$font" --glyphs "$([ "$glyphs" = all ] && echo all)" | tail -1
  for gate in g1-between-masters g1-between-masters:1 curvature-between-masters extrema-between-masters; do
    rm -rf "$out/qa"
    /usr/bin/time -f "%e s wall, %M KB peak" -o "$out/time" "$build/tools/cmr" report "$font" --require "$gate" \
      --glyphs "$glyphs" --no-thumbnails --jobs 2 --out "$out/qa" > "$out/stdout" 2> "$out/stderr"
    rc=$?
    echo "cmr $gate: exit $rc, $(tail -1 "$out/stdout" | sed 's/; wrote.*//'); $(tail -1 "$out/time")"
    grep -c '^cmr: ' "$out/stderr" | xargs -I{} echo "  {} lines on stderr, first: $(grep -m1 '^cmr: ' "$out/stderr")"
  done
  "$build/tools/bench/bench_between" "$font" "$glyphs"
done
