#!/usr/bin/env python3
"""How `cmr region --point all` scales with the number of control points.

Generates uniform cubic B-splines of N points (a wave: x = i/2,
y = sin(0.3 i), so every point's region is computed over the same kind of
curve) and times `cmr region FILE --point all --backend cpu` on each. The
time per point should stay flat (linear scaling); before the setup was
shared across points it grew with N (quadratic).

    python3 tools/bench/point_all_scaling.py [--cmr build/tools/cmr]
        [--before OTHER_CMR] [--sizes 125,250,500,1000] [--image 128x128]

Prints one row per N: wall seconds, CPU seconds (user + sys of the child:
less sensitive to other load on the machine) and CPU milliseconds per point.
"""
import argparse
import json
import math
import os
import resource
import subprocess
import sys
import tempfile
import time


def spline(n):
    return {"degree": 3, "knots": list(range(n + 2)),
            "points": [[i * 0.5, round(math.sin(i * 0.3), 6)] for i in range(n)]}


def run(cmr, path, image):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.monotonic()
    out = subprocess.run([cmr, "region", path, "--point", "all", "--backend", "cpu", "--size", image],
                         check=True, capture_output=True, text=True).stdout
    wall = time.monotonic() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    points = len(json.loads(out)["points"])
    return wall, cpu, points


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cmr", default="build/tools/cmr")
    ap.add_argument("--before", help="another cmr binary to compare with (e.g. an older build)")
    ap.add_argument("--sizes", default="125,250,500,1000")
    ap.add_argument("--image", default="128x128")
    a = ap.parse_args()
    sizes = [int(s) for s in a.sizes.split(",")]
    binaries = [("cmr", a.cmr)] + ([("before", a.before)] if a.before else [])
    print(f"cmr region --point all --backend cpu --size {a.image}; wave splines of N points; "
          f"{os.cpu_count()} hardware threads")
    print(f"{'binary':>8} {'N':>6} {'wall s':>8} {'cpu s':>8} {'cpu ms/point':>13}")
    with tempfile.TemporaryDirectory() as tmp:
        for n in sizes:
            path = os.path.join(tmp, f"wave{n}.json")
            with open(path, "w") as f:
                json.dump(spline(n), f)
            for name, exe in binaries:
                wall, cpu, points = run(exe, path, a.image)
                if points != n:
                    sys.exit(f"{name}: {points} points in the summary, expected {n}")
                print(f"{name:>8} {n:>6} {wall:8.2f} {cpu:8.2f} {1000 * cpu / n:13.2f}", flush=True)


if __name__ == "__main__":
    main()
