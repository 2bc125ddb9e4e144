#!/bin/bash
# What the resume cache of cmr report saves (report/report_cache.hpp,
# docs/interpolation.md "Resumable reports"): on a variable font, for each
# glyph set and gate, a first run into an empty folder (every glyph judged,
# the cache written), a rerun into the same folder (every glyph taken from
# the cache), and a fresh --no-cache run, each timed; then whether the
# rerun's report.json equals the fresh run's, byte for byte.
#   tools/bench/report_cache_bench.sh [BUILD_DIR] [FONT] [GATES...]
# Defaults: build, Inter roman (Debian fonts-inter-variable),
# g1-between-masters and curvature-between-masters. Timings only: the
# byte-identity line is the one check.
set -u
build=${1:-build}
font=${2:-/usr/share/fonts/truetype/inter-vf/Inter-roman.var.ttf}
gates=("${@:3}")
[ ${#gates[@]} -eq 0 ] && gates=(g1-between-masters curvature-between-masters)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'); $(uptime | sed 's/.*load/load/')"
echo "font: $font"
cmr=$build/tools/cmr
timed() {  # timed NAME ARGS...: runs cmr report, prints its wall time and the cache's note
  local name=$1
  shift
  /usr/bin/time -f "%e" -o "$out/time" "$cmr" report "$@" > "$out/stdout" 2> "$out/stderr"
  local rc=$?
  local note
  note=$(grep -m1 'report.cache: ' "$out/stderr" | sed 's/.*report.cache: //')
  printf '  %-8s exit %d, %6.2f s%s\n' "$name" "$rc" "$(tail -1 "$out/time")" "${note:+ ($note)}"
}
for glyphs in A-Z,a-z all; do
  for gate in "${gates[@]}"; do
    echo "== glyphs $glyphs, $gate (--jobs 2 --no-thumbnails)"
    args=("$font" --require "$gate" --glyphs "$glyphs" --no-thumbnails --jobs 2)
    rm -rf "$out/qa" "$out/fresh"
    timed first "${args[@]}" --out "$out/qa"
    timed rerun "${args[@]}" --out "$out/qa"
    timed fresh "${args[@]}" --no-cache --out "$out/fresh"
    if cmp -s "$out/qa/report.json" "$out/fresh/report.json" && cmp -s "$out/qa/font.html" "$out/fresh/font.html"; then
      echo "  rerun's report.json and font.html: byte-identical to the fresh run's"
    else
      echo "  rerun's report differs from the fresh run's"
    fi
    echo "  cache: $(stat -c %s "$out/qa/report.cache") bytes; report.json $(stat -c %s "$out/qa/report.json") bytes"
  done
done
echo "load after: $(uptime | sed 's/.*load/load/')"
