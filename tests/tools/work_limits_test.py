#!/usr/bin/python3
"""Work and memory bounded by the input, outside `report` (issue 42 item 7).

Each reproducer of the review is generated here and run under a memory
ceiling (RLIMIT_AS, as `ulimit -v`) and a wall-clock limit:

- `cmr sweep`: its pixel limit is set by memory as well as by count: a
  sweep that would need more than 3/4 of ulimit -v (about 100 bytes a
  pixel) is refused at once with one line and exit 2; one that fits runs
  under the same ceiling;
- a space `region` with weights 1e300 and 1e-300 (exact arithmetic at
  ~9 ms a pixel): a 2048 x 2048 render stops with one line and exit 2
  well within its 60 s budget, and writes nothing; a plain one still runs;
- `report --baseline`: a baseline of 60 MB (under the 64 MiB input limit)
  is read under ulimit -v 1.5 GB.

Usage: work_limits_test.py CMR SOURCE_DIR WORKDIR
"""
import json
import os
import resource
import shutil
import subprocess
import sys
import time

CMR = os.path.abspath(sys.argv[1])
SRC = os.path.abspath(sys.argv[2])
WORK = sys.argv[3]
MB = 1024 * 1024
if os.environ.get("CMR_SANITIZER_BUILD") == "1":
    # Every check here runs cmr under RLIMIT_AS (ulimit -v), and an ASan
    # program cannot start under one: it reserves terabytes of shadow address
    # space. The Release suite (CI) runs these checks.
    print("skipped in a sanitizer build: ASan cannot run under ulimit -v")
    sys.exit(77)
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def run(args, limit_mb, timeout):
    """cmr ARGS under RLIMIT_AS = limit_mb: (rc, stderr lines, seconds); rc None: timed out."""
    def limits():
        resource.setrlimit(resource.RLIMIT_AS, (limit_mb * MB, limit_mb * MB))
    t0 = time.monotonic()
    try:
        p = subprocess.run([CMR] + args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, preexec_fn=limits,
                           cwd=WORK, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None, [], time.monotonic() - t0
    lines = [l for l in p.stderr.decode(errors="replace").splitlines() if l.strip() and not l.startswith("note: no GPU")]
    return p.returncode, lines, time.monotonic() - t0


shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
fig8 = os.path.join(SRC, "examples", "figures", "fig8.json")
sweep = ["sweep", fig8, "--point", "3", "--knot", "3", "--from", "2.1", "--to", "3.9", "--backend", "cpu"]

# sweep: 16 steps of 1024 x 1024 need ~1.6 GB: refused at once under 1 GB; 4 of 512 x 512 run.
rc, err, s = run(sweep + ["--steps", "15", "--size", "1024x1024", "--out-dir", "big"], 1024, 60)
check(rc == 2 and len(err) == 1 and "bytes a pixel" in err[0] and s < 10,
      f"sweep 16 x 1024^2 under ulimit -v 1 GB: exit 2, one line, at once ({rc}, {s:.1f} s: {err})")
check(not os.path.exists(os.path.join(WORK, "big")), "sweep refused: nothing written")
rc, err, s = run(sweep + ["--steps", "3", "--size", "512x512", "--out-dir", "small"], 1024, 300)
check(rc == 0 and os.path.exists(os.path.join(WORK, "small", "tube.obj")),
      f"sweep 4 x 512^2 under ulimit -v 1 GB: runs ({rc}: {err})")

# space region with weights 1e300 and 1e-300.
with open(os.path.join(SRC, "examples", "space", "fig8b_lifted_rational.json")) as f:
    spline = json.load(f)
spline["weights"] = [1, 1e300, 1e-300, 1, 1e300, 1]
with open(os.path.join(WORK, "extreme.json"), "w") as f:
    json.dump(spline, f)
rc, err, s = run(["region", "extreme.json", "--point", "2", "--size", "2048x2048", "--png", "extreme.png"], 2048, 200)
check(rc == 2 and len(err) == 1 and "limit of 60 s per render" in err[0] and s < 70,
      f"space region, weights 1e300/1e-300, 2048^2: exit 2 and one line within the 60 s budget ({rc}, {s:.1f} s: {err})")
check(not os.path.exists(os.path.join(WORK, "extreme.png")), "space region stopped: nothing written")
rc, err, s = run(["region", os.path.join(SRC, "examples", "space", "fig8b_lifted_rational.json"), "--point", "2",
                  "--size", "64x64", "--png", "plain.png"], 2048, 200)
check(rc == 0 and os.path.exists(os.path.join(WORK, "plain.png")), f"space region, plain weights: runs ({rc}: {err})")

# report --baseline: 60 MB of findings under ulimit -v 1.5 GB.
with open(os.path.join(WORK, "base.json"), "w") as f:
    f.write('{"schema":"cmr-report/2","splines":[')
    n = 0
    while f.tell() < 60 * MB:
        f.write(("," if n else "") + '{"id":"s%d","name":"g%d","status":"fail","findings":[' % (n, n) +
                ",".join('{"key":"a.svg|g%d|c0|p%d|curvature-extrema-at-nodes"}' % (n, k) for k in range(20)) + "]}")
        n += 1
    f.write("]}")
rc, err, s = run(["report", fig8, "--out", "withbase", "--baseline", "base.json", "--no-thumbnails"], 1536, 300)
check(rc in (0, 1) and not any("memory" in l for l in err),
      f"report --baseline of 60 MB under ulimit -v 1.5 GB: read ({rc}, {s:.1f} s: {err[-1:] if err else ''})")

print(f"{len(failures)} failed")
sys.exit(1 if failures else 0)
