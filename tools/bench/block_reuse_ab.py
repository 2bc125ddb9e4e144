#!/usr/bin/env python3
"""A/B of the region block-proof reuse (region/box_reuse.hpp): runs
`bench_region N "VIEW D SIZE" cmr` with CMR_BLOCK_REUSE=1 and =0, interleaved
(each round runs both, in turn, so load falls on both alike), for every view,
D and size, and prints a Markdown table of the best CPU ms (every thread of
the process) per cell and the ratio off/on.

Run from the repository root after building bench_region:
  VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json \\
    python3 tools/bench/block_reuse_ab.py [rounds] [reps per run]
"""
import collections
import os
import re
import subprocess
import sys

ROUNDS = int(sys.argv[1]) if len(sys.argv) > 1 else 3
REPS = sys.argv[2] if len(sys.argv) > 2 else "10"
BENCH = "build/tools/bench/bench_region"
LINE = re.compile(r"\s*(.*?)\s+cmr CPU\s+([\d.]+) ms wall\s+([\d.]+) ms CPU")

best = collections.OrderedDict()
for view in ("whole region", "10x wider", "4e-4 zoom"):
    for depth in (10, 16):
        for size in (512, 1024):
            for _ in range(ROUNDS):
                for on in ("1", "0"):
                    env = dict(os.environ, CMR_BLOCK_REUSE=on)
                    out = subprocess.run([BENCH, REPS, f"{view} {depth} {size}", "cmr"], env=env,
                                         capture_output=True, text=True, check=True).stdout
                    for line in out.splitlines():
                        m = LINE.match(line)
                        if not m:
                            continue
                        key = re.sub(r"\s+", " ", m.group(1))
                        cell = best.setdefault(key, {"1": float("inf"), "0": float("inf")})
                        cell[on] = min(cell[on], float(m.group(3)))

print("| cell (scene, view, D, size) | reuse off, CPU ms | reuse on, CPU ms | off / on |")
print("|---|---:|---:|---:|")
for key, v in best.items():
    print(f"| {key} | {v['0']:.2f} | {v['1']:.2f} | {v['0'] / v['1']:.2f} |")
