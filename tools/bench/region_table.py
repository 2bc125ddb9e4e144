#!/usr/bin/env python3
"""The README's ratio table from a bench_region run.

Usage: build/tools/bench/bench_region 10 > run.txt; python3 tools/bench/region_table.py run.txt

Reads the baseline table bench_region prints (one row per scene, view, D and
size) and writes, as Markdown, one row per scene and view and one column per
D and size, each cell "CPU / Vulkan" = cmr's wall-clock rate divided by the
fastest baseline's (the native, vectorised and shader forms of the published
method) in that cell, the cells below issue 23's targets (CPU 5x, Vulkan 2x)
in bold, and the machine line of the run.
"""
import re
import sys

ROW = re.compile(r"^\s{2}(\S.{18}\S?)\s+(whole region|10x wider|4e-4 zoom)\s+(\d+)\s+(\d+)\s+"
                 r"(?:[\d.]+\s+){5}([\d.]+)x\s+([\d.]+)x")


def main(path):
    text = open(path, encoding="utf-8").read()
    machine = next((l for l in text.splitlines() if l.startswith("cmr region benchmark:")), "")
    cells, scenes, columns = {}, [], []
    for line in text.splitlines():
        m = ROW.match(line)
        if not m:
            continue
        scene, view, depth, size = m.group(1).strip(), m.group(2), int(m.group(3)), int(m.group(4))
        cpu, vk = float(m.group(5)), float(m.group(6))
        key = (scene, view)
        if key not in scenes:
            scenes.append(key)
        col = (depth, size)
        if col not in columns:
            columns.append(col)
        cells[(key, col)] = (cpu, vk)
    if not cells:
        sys.exit(f"region_table: no baseline rows in {path}")
    print(f"`{machine.strip()}`\n")
    print("| scene | view | " + " | ".join(f"D = {d}, {s}²" for d, s in columns) + " |")
    print("|---|---|" + "---:|" * len(columns))
    for scene, view in scenes:
        out = []
        for col in columns:
            cpu, vk = cells.get(((scene, view), col), (float("nan"), float("nan")))
            c = f"{cpu:.1f}" if cpu >= 5 else f"**{cpu:.1f}**"
            v = f"{vk:.1f}" if vk >= 2 else f"**{vk:.1f}**"
            out.append(f"{c} / {v}")
        print(f"| {scene} | {view} | " + " | ".join(out) + " |")
    met_cpu = sum(1 for c in cells.values() if c[0] >= 5)
    met_vk = sum(1 for c in cells.values() if c[1] >= 2)
    print(f"\nCPU ≥ 5× in {met_cpu} of {len(cells)} cells; Vulkan ≥ 2× in {met_vk} of {len(cells)}.")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: region_table.py BENCH_REGION_OUTPUT")
    main(sys.argv[1])
