#!/usr/bin/env bash
# Builds the libFuzzer harnesses (clang, ASan + UBSan) in build-fuzz and runs
# each for SECONDS (default 10) at the lowest priority, as many at once as
# there are cores (CMR_FUZZ_JOBS overrides; each harness is one process).
#   fuzz/run.sh [SECONDS] [HARNESS...]      e.g. fuzz/run.sh 600 svg_document
# A finding stops that harness with its crash file in build-fuzz/findings/
# and makes the script exit 1. Seeds: fuzz/corpus/NAME (read only; new inputs
# go to build-fuzz/corpus/NAME); dictionaries: fuzz/dict/NAME.dict.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-10}
shift || true
all=(spline_json svg_document svg_path font kcurve knot_ops analyze region_classify glif ufo designspace location py_dict obj stdin)
# -O1 and line tables only (libFuzzer's own recommendation is -g -O1): a
# finding's stack still names file and line, and the build, which CI runs
# cold, takes less time than at -O2 with full debug information.
cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only -DNDEBUG" \
  -DCMR_FUZZ=ON -DCMR_SANITIZER_BUILD=ON -DCMR_BUILD_TESTS=OFF -DCMR_BUILD_BENCHMARKS=OFF -DCMR_WITH_VULKAN=OFF -DCMR_BUILD_EDITOR=OFF \
  -DCMAKE_CXX_FLAGS="-fsanitize=address,undefined,fuzzer-no-link -fno-sanitize-recover=undefined -fno-omit-frame-pointer" \
  >/dev/null
# fuzz_step where the build has the STEP importer (OpenCASCADE found).
grep -q 'build fuzz/fuzz_step:' build-fuzz/build.ninja && all+=(step)
names=("$@")
((${#names[@]})) || names=("${all[@]}")
ninja -C build-fuzz -j"${CMR_FUZZ_JOBS:-2}" "${names[@]/#/fuzz/fuzz_}"
mkdir -p build-fuzz/findings
# fuzz_one NAME: runs one harness; its summary goes to build-fuzz/findings/NAME.result
# (printed in order at the end, so parallel runs do not interleave), and it
# returns non-zero on a finding.
fuzz_one() {
  local n=$1
  mkdir -p "build-fuzz/corpus/$n"
  # The font seeds are small complete fonts from Debian packages (tools/setup.sh),
  # not committed: a TrueType one (glyf, 4.5 KB; fuzz_font imports its Lycian
  # letters) and a CFF one (21 KB; A-C and o are Greek capitals and omicron
  # there), both well under -max_len, so the fuzzer mutates whole fonts.
  if [[ $n == font ]]; then
    for seed in /usr/share/fonts/truetype/noto/NotoSansLycian-Regular.ttf \
                /usr/share/fonts/opentype/urw-base35/StandardSymbolsPS.otf; do
      [[ -f $seed ]] && cp -n "$seed" build-fuzz/corpus/font/
    done
    rm -f build-fuzz/corpus/font/dejavu.ttf  # the old seed: cut to its first 64 KiB by -max_len
  fi
  dict=()
  [[ -f fuzz/dict/$n.dict ]] && dict=(-dict="fuzz/dict/$n.dict")
  [[ $n == stdin ]] && dict=(-dict=fuzz/dict/spline_json.dict)  # spline files through standard input
  # OpenCASCADE's STEP reader leaks what it read of some malformed entities
  # (RWStepGeom_RWDirection::ReadStep's arrays): not cmr's memory, so
  # LeakSanitizer is off for fuzz_step (ASan and UBSan stay on).
  # LeakSanitizer's own check at exit is off too (ASAN_OPTIONS), or those
  # leaks end the run as a finding.
  # fuzz_step runs single-threaded: read_step_curves forks its crash probe
  # only when no other thread runs (step_occt.cpp), and libFuzzer's RSS
  # limit is a thread, so for step the limit is -malloc_limit_mb (checked in
  # malloc, no thread). With the thread, the probe was skipped and an
  # OpenCASCADE crash the probe refuses in `cmr import` ended the fuzzer.
  envs=()
  limits=(-rss_limit_mb=2048)
  [[ $n == step ]] && dict+=(-detect_leaks=0) && envs=(ASAN_OPTIONS=detect_leaks=0) && limits=(-rss_limit_mb=0 -malloc_limit_mb=2048)
  rm -f build-fuzz/findings/"$n"-*  # a finding of an earlier run is not this run's
  start=$(date +%s)
  # -timeout is wall-clock time: at nice 19 on a loaded machine a 0.3 s input
  # of fuzz_kcurve was once stopped after 29 s (20 s allowed), not a hang.
  if nice -n 19 env "${envs[@]}" "build-fuzz/fuzz/fuzz_$n" -max_total_time="$seconds" -max_len=65536 -timeout=60 "${limits[@]}" \
      -artifact_prefix="build-fuzz/findings/$n-" "${dict[@]}" "build-fuzz/corpus/$n" "fuzz/corpus/$n" \
      >"build-fuzz/findings/$n.log" 2>&1; then
    # libFuzzer ends with "Done RUNS runs in SECONDS second(s)".
    echo "fuzz $n: $(( $(date +%s) - start )) s, no finding ($(grep -o 'Done [0-9]* runs in [0-9]* second' "build-fuzz/findings/$n.log" | tail -1 | sed 's/second/s of fuzzing/' || echo '? runs'))"
  else
    echo "fuzz $n: FINDING after $(( $(date +%s) - start )) s; see build-fuzz/findings/$n.log"
    # What CI keeps is this output, not build-fuzz: the report's first lines
    # and the input that caused it (base64, at most 4 KiB), to reproduce with
    #   base64 -d > crash && build-fuzz/fuzz/fuzz_$n crash
    grep -m1 -A30 -E '==[0-9]+==|runtime error|deadly signal|out-of-memory|timeout|leak' "build-fuzz/findings/$n.log" | sed 's/^/  /' || true
    for crash in build-fuzz/findings/"$n"-*; do
      [[ -f $crash ]] || continue
      echo "  input $crash ($(stat -c %s "$crash") bytes), base64:"
      head -c 4096 "$crash" | base64 | sed 's/^/    /'
    done
    return 1
  fi
}
parallel=${CMR_FUZZ_JOBS:-$(nproc)}
for n in "${names[@]}"; do
  while (($(jobs -rp | wc -l) >= parallel)); do wait -n || true; done
  fuzz_one "$n" >"build-fuzz/findings/$n.result" 2>&1 &
done
wait
status=0
for n in "${names[@]}"; do
  cat "build-fuzz/findings/$n.result"
  # Only a harness that said "no finding" passed (a finding, or a script error
  # in its subshell, leaves no such line).
  grep -q '^fuzz [a-z_]*: [0-9]* s, no finding' "build-fuzz/findings/$n.result" || status=1
done
exit $status
