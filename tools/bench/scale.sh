#!/usr/bin/env bash
# Scale benchmark (issue 23, item 4): `cmr analyze` of one cubic B-spline of
# 10^6 spans, and `cmr report` of 10,000 spline files, each under
# /usr/bin/time -v (wall time, CPU time, peak resident memory). The inputs
# are generated deterministically (seeded) by the embedded Python:
#   * long.json: a uniform cubic B-spline with 10^6 + 3 control points on a
#     random walk of turning angles (seed 23): a wiggly curve with an
#     inflection every few spans, so the exact-inflection path is exercised;
#   * batch/NNNNN.json: 10,000 cubic B-splines of 10 spans (13 points marching
#     along x with random heights, seed 6; bench_report's family).
# Usage: tools/bench/scale.sh [CMR] [OUT]   (CMR default build/tools/cmr, OUT /tmp/cmr-scale)
# Environment: SPANS=N (default 1000000), SPLINES=N (default 10000);
# REFERENCE=CMR also runs that binary's analyze and compares the outputs.
# Targets: analyze <= 10 s and <= 1 GB; report <= 10 s wall; on 2 cores.
# On a shared machine wall time measures the load: CPU time and the cores
# kept busy are the fair figures (wall on free cores ~ CPU / cores busy).
set -euo pipefail
cmr=${1:-build/tools/cmr}
out=${2:-/tmp/cmr-scale}
spans=${SPANS:-1000000}
splines=${SPLINES:-10000}
rm -rf "$out"
mkdir -p "$out/batch"
python3 - "$out" "$spans" "$splines" <<'PY'
import json, math, random, sys
out, spans, splines = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
rng = random.Random(23)
n = spans + 3
x = y = 0.0
heading = 0.0
turn = 0.0
pts = []
for i in range(n):
    # The turning angle itself wanders and changes sign: inflections.
    turn = 0.85 * turn + rng.uniform(-0.35, 0.35)
    heading += turn
    x += math.cos(heading)
    y += math.sin(heading)
    pts.append([round(x, 6), round(y, 6)])
knots = list(range(n + 3 - 1))  # polar form: points + degree - 1
with open(f"{out}/long.json", "w") as f:
    f.write('{"name": "random walk, %d spans", "degree": 3, "knots": [' % spans)
    f.write(",".join(str(k) for k in knots))
    f.write('], "points": [')
    f.write(",".join("[%r,%r]" % (p[0], p[1]) for p in pts))
    f.write("]}\n")
rng = random.Random(6)
for s in range(splines):
    p = [[i + rng.uniform(-0.3, 0.3), rng.uniform(-1.0, 1.0)] for i in range(13)]
    with open(f"{out}/batch/{s:05d}.json", "w") as f:
        json.dump({"name": f"random {s}", "degree": 3, "knots": list(range(15)), "points": p}, f)
PY
echo "scale: $(nproc) cores:$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2); load average $(cut -d' ' -f1-3 /proc/loadavg)"
measure() {  # NAME COMMAND...
  local name=$1; shift
  set +e
  /usr/bin/time -v -o "$out/$name.time" "$@" >"$out/$name.out" 2>"$out/$name.err"
  local rc=$?
  set -e
  if ((rc != 0 && rc != 1)); then echo "scale: $name failed ($rc)"; tail -3 "$out/$name.err"; exit 1; fi
  local wall user sys rss cpu
  wall=$(grep 'Elapsed (wall clock)' "$out/$name.time" | awk '{print $NF}')
  user=$(grep 'User time' "$out/$name.time" | awk '{print $NF}')
  sys=$(grep 'System time' "$out/$name.time" | awk '{print $NF}')
  rss=$(grep 'Maximum resident set size' "$out/$name.time" | awk '{print $NF}')
  cpu=$(grep 'Percent of CPU' "$out/$name.time" | awk '{print $NF}')
  # CPU / wall: how many cores the run kept busy on average (a loaded
  # machine lowers it; on free cores it is the parallelism reached).
  echo "scale: $name: wall $wall, CPU ${user} s user + ${sys} s sys ($cpu of one core), peak memory $((rss / 1024)) MiB"
}
# analyze runs its spans on every core of its CPU affinity (taskset limits it).
measure analyze "$cmr" analyze "$out/long.json"
echo "scale: analyze output $(du -h "$out/analyze.out" | cut -f1)"
if [[ -n ${REFERENCE:-} ]]; then  # REFERENCE=OTHER_CMR: its output must be byte for byte the same
  measure reference "$REFERENCE" analyze "$out/long.json"
  if cmp -s "$out/analyze.out" "$out/reference.out"; then echo "scale: analyze output identical to $REFERENCE's"
  else echo "scale: analyze output DIFFERS from $REFERENCE's"; exit 1; fi
fi
measure report "$cmr" report "$out/batch" --no-thumbnails --quiet --out "$out/report"
echo "scale: report: $(tail -1 "$out/report.out")"
echo "scale: load average after $(cut -d' ' -f1-3 /proc/loadavg)"
