#!/usr/bin/env python3
"""A/B of two bench_region binaries (e.g. built from two commits): runs
`BIN REPS "CELL" cmr` for each binary in turn, cell by cell, ROUNDS times
(interleaved, so load falls on both alike), and prints a Markdown table of
the best and median CPU ms (every thread of the process) and wall ms per
cell and the ratios of the best.

Run from the repository root:
  VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json \\
    python3 tools/bench/region_ab.py OLD_BIN NEW_BIN [rounds] [reps] [cell ...]
"""
import collections
import re
import statistics
import subprocess
import sys

from region_cells import DEFAULT_CELLS

if len(sys.argv) < 3:
    sys.stderr.write("usage: region_ab.py OLD_BIN NEW_BIN [rounds] [reps] [cell ...]\n")
    sys.exit(2)
OLD, NEW = sys.argv[1], sys.argv[2]
ROUNDS = int(sys.argv[3]) if len(sys.argv) > 3 else 5
REPS = sys.argv[4] if len(sys.argv) > 4 else "30"
CELLS = sys.argv[5:] or DEFAULT_CELLS
LINE = re.compile(r"\s*(.*?)\s+cmr CPU\s+([\d.]+) ms wall\s+([\d.]+) ms CPU")

cpu = collections.defaultdict(list)
wall = collections.defaultdict(list)
for _ in range(ROUNDS):
    for cell in CELLS:
        for name, binary in (("old", OLD), ("new", NEW)):
            out = subprocess.run([binary, REPS, cell, "cmr"], capture_output=True, text=True, check=True).stdout
            m = [LINE.match(l) for l in out.splitlines()]
            m = [x for x in m if x]
            if len(m) != 1:
                sys.stderr.write(f"region_ab.py: cell '{cell}' matched {len(m)} rows of {binary}\n")
                sys.exit(1)
            cpu[(cell, name)].append(float(m[0].group(3)))
            wall[(cell, name)].append(float(m[0].group(2)))

print("| cell | old CPU ms (best / median) | new CPU ms (best / median) | old/new (best) "
      "| old wall ms (best / median) | new wall ms (best / median) | old/new wall (best) |")
print("|---|---|---|---|---|---|---|")
for cell in CELLS:
    o, n = cpu[(cell, "old")], cpu[(cell, "new")]
    ow, nw = wall[(cell, "old")], wall[(cell, "new")]
    print(f"| {cell} | {min(o):.3f} / {statistics.median(o):.3f} | {min(n):.3f} / {statistics.median(n):.3f} "
          f"| {min(o) / min(n):.2f}x | {min(ow):.3f} / {statistics.median(ow):.3f} "
          f"| {min(nw):.3f} / {statistics.median(nw):.3f} | {min(ow) / min(nw):.2f}x |")
