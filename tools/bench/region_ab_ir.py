#!/usr/bin/env python3
"""A/B of two bench_region binaries by counted work, not by the clock: runs
each cell under valgrind's cachegrind (simulated caches) with R and R + K
frames (`BIN R "CELL" cmr`) and takes the difference divided by K, so the
program's start and the scene's setup drop out. Prints, per cell and frame,
the instructions executed (Ir), first-level data cache misses (D1), last-
level misses (LL), and a cycle estimate Ir + 10 D1 + 100 LL (the usual
cachegrind weighting), for OLD and NEW, and NEW/OLD of each.

A quiet measure for a shared machine: the counts do not depend on the load
(wall-clock A/B, region_ab.py, scatters by +-5-20 % between rounds there).
They are not times: a branch mispredicted or a pipeline stall costs nothing
here. Threads run one at a time under valgrind; their total work is counted.
Needs valgrind (tools/setup.sh installs it). Run from the repository root:

  python3 tools/bench/region_ab_ir.py OLD_BIN NEW_BIN [K] [cell ...]
"""
import re
import subprocess
import sys

from region_cells import DEFAULT_CELLS

if len(sys.argv) < 3:
    sys.stderr.write("usage: region_ab_ir.py OLD_BIN NEW_BIN [K] [cell ...]\n")
    sys.exit(2)
OLD, NEW = sys.argv[1], sys.argv[2]
K = int(sys.argv[3]) if len(sys.argv) > 3 else 3
R = 1
CELLS = sys.argv[4:] or DEFAULT_CELLS
FIELDS = {"Ir": r"I\s+refs:\s+([\d,]+)", "D1": r"D1\s+misses:\s+([\d,]+)", "LL": r"LL misses:\s+([\d,]+)"}


def counts(binary, reps, cell):
    """cachegrind's totals of one run: Ir, D1 misses (reads and writes), LL misses."""
    run = subprocess.run(
        ["valgrind", "--tool=cachegrind", "--cache-sim=yes", "--cachegrind-out-file=/dev/null",
         binary, str(reps), cell, "cmr"], capture_output=True, text=True)
    if run.returncode != 0:
        sys.stderr.write(f"region_ab_ir.py: {binary} {reps} '{cell}' cmr exited {run.returncode}:\n{run.stderr[-2000:]}")
        sys.exit(1)
    if sum(1 for line in run.stdout.splitlines() if " cmr CPU " in line) != 1:
        sys.stderr.write(f"region_ab_ir.py: cell '{cell}' is not one row of {binary}\n")
        sys.exit(1)
    out = {}
    for key, pattern in FIELDS.items():
        m = re.search(pattern, run.stderr)
        if not m:
            sys.stderr.write(f"region_ab_ir.py: no '{key}' in valgrind's summary of {binary}\n")
            sys.exit(1)
        out[key] = int(m.group(1).replace(",", ""))
    return out


def per_frame(binary, cell):
    a, b = counts(binary, R, cell), counts(binary, R + K, cell)
    f = {key: (b[key] - a[key]) / K for key in FIELDS}
    f["est"] = f["Ir"] + 10 * f["D1"] + 100 * f["LL"]
    return f


print(f"per frame (difference of {R} and {R + K} frames, / {K}); est = Ir + 10 D1 + 100 LL")
print("| cell | old Ir (M) | new Ir (M) | new/old Ir | old D1 (k) | new D1 (k) | old LL (k) | new LL (k) "
      "| new/old est |")
print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
for cell in CELLS:
    o, n = per_frame(OLD, cell), per_frame(NEW, cell)
    print(f"| {cell} | {o['Ir'] / 1e6:.2f} | {n['Ir'] / 1e6:.2f} | {n['Ir'] / o['Ir']:.4f} "
          f"| {o['D1'] / 1e3:.1f} | {n['D1'] / 1e3:.1f} | {o['LL'] / 1e3:.1f} | {n['LL'] / 1e3:.1f} "
          f"| {n['est'] / o['est']:.4f} |", flush=True)
