#!/usr/bin/env python3
"""The speed points of issue 38 for `import cmr` (docs/python.md, "Speed"):

 1. cmr.analyze on a cubic Bezier against the C++ call, in loops of 10,000
    (the binding's and the dict's overhead): the C++ loop is timed inside
    the module (cmr._cmr._time_analyze, no Python in between);
 2. cmr.region: the labels come back in one pass (the render's time, the
    command's summary "seconds", against the whole call);
 3. 10,000 glyph contours through the pen (fontTools -> SplinePen ->
    cmr.judge, as `cmr report` judges them) against `cmr report` on the same
    glyphs (--no-thumbnails, and --no-severity: judging alone, as the pen's
    verdicts), on as many threads as cores.

    PYTHONPATH=build/python /usr/bin/python3 tools/bench/python_overhead.py [CMR_EXE]

Benchmarks, not tests: nothing is asserted.
"""

import glob
import os
import platform
import subprocess
import sys
import tempfile
import time

import cmr
import cmr.fonttools

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CMR = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "tools", "cmr")


def best(f, repeat=3):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        f()
        times.append(time.perf_counter() - t0)
    return min(times)


def machine():
    cpu = "?"
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(l.split(":", 1)[1].strip() for l in f if l.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return f"{cpu}, {os.cpu_count()} hardware threads, Python {platform.python_version()}, load {os.getloadavg()[0]:.2f}"


def bench_analyze(n=10000, rounds=15):
    """Each of the four loops `rounds` times, interleaved, best of each: the
    machine's load (other builds) slows all of them alike within a round."""
    bezier = cmr.Spline(3, [[0, 0], [1, 2], [3, 3], [4, 0]])
    d = bezier.to_dict()
    loops = {
        "cpp": lambda: cmr._cmr._time_analyze(bezier, n),
        "cpp_read": lambda: cmr._cmr._time_analyze(bezier, n, False, True),
        "cpp_doc": lambda: cmr._cmr._time_analyze(bezier, n, True),
        "py_spline": lambda: best(lambda: [cmr.analyze(bezier) for _ in range(n)], 1),
        "py_dict": lambda: best(lambda: [cmr.analyze(d) for _ in range(n)], 1),
    }
    t = {k: float("inf") for k in loops}
    for _ in range(rounds):
        for k, f in loops.items():
            t[k] = min(t[k], f())
    us = {k: v / n * 1e6 for k, v in t.items()}
    print(f"1. cmr.analyze, cubic Bezier, loop of {n} (best of {rounds}, interleaved):")
    print(f"   C++ analyze()                        {us['cpp']:7.2f} us/call")
    print(f"   C++ spline_from_json() + analyze()   {us['cpp_read']:7.2f} us/call")
    print(f"   C++ analyze() + document tree        {us['cpp_doc']:7.2f} us/call")
    print(f"   cmr.analyze(cmr.Spline)              {us['py_spline']:7.2f} us/call  = "
          f"{t['py_spline'] / t['cpp']:.2f}x analyze()")
    print(f"   cmr.analyze(dict)                    {us['py_dict']:7.2f} us/call  = "
          f"{t['py_dict'] / t['cpp_read']:.2f}x spline_from_json() + analyze(), {t['py_dict'] / t['cpp']:.2f}x analyze()")


def bench_region():
    fig8 = cmr.Spline.load(os.path.join(ROOT, "examples/figures/fig8.json"))
    print("2. cmr.region, Fig. 8 P3, default view, CPU backend (best of 5):")
    for side in (512, 1024, 2048):
        runs = []
        for _ in range(5):
            t0 = time.perf_counter()
            r = cmr.region_result(fig8, point=3, size=(side, side), backend="cpu")
            runs.append((time.perf_counter() - t0, r["summary"]["seconds"]))
        whole, render = min(runs)
        plain = best(lambda: cmr.region(fig8, point=3, size=(side, side), backend="cpu"), 5)
        print(f"   {side}x{side}: cmr.region {plain * 1e3:7.2f} ms; region_result {whole * 1e3:7.2f} ms, of which "
              f"the render {render * 1e3:7.2f} ms ({side * side / 1e6:.1f} MB of labels written once)")


GLYPHS = "A-Z,a-z,0-9,U+00C0-U+00FF"  # Latin letters, digits, Latin-1 accented letters
CODEPOINTS = ([*range(ord("A"), ord("Z") + 1), *range(ord("a"), ord("z") + 1), *range(ord("0"), ord("9") + 1),
               *range(0xC0, 0x100)])


def fonts_for(contours_wanted):
    """Latin fonts (those with A-Z, a-z) and their glyphs of GLYPHS until
    `contours_wanted` contours."""
    from fontTools.ttLib import TTFont
    candidates = sorted(glob.glob("/usr/share/fonts/truetype/dejavu/*.ttf") +
                        glob.glob("/usr/share/fonts/opentype/urw-base35/*.otf") +
                        glob.glob("/usr/share/texmf/fonts/opentype/public/tex-gyre/*.otf") +
                        glob.glob("/usr/share/fonts/truetype/noto/*.ttf"))
    chosen, total = [], 0
    for path in candidates:
        try:
            font = TTFont(path)
        except Exception:  # noqa: BLE001 (a file fontTools cannot read is skipped)
            continue
        cmap = font.getBestCmap() or {}
        if any(c not in cmap for c in range(ord("A"), ord("z") + 1) if chr(c).isalpha()):
            continue
        names = [cmap[c] for c in CODEPOINTS if c in cmap]
        glyphs = font.getGlyphSet()
        count = sum(len(cmr.fonttools.glyph_contours(glyphs, n)) for n in names)
        chosen.append((path, names, count))
        total += count
        if total >= contours_wanted:
            break
    return chosen, total


def bench_pen(contours_wanted=10000):
    from fontTools.ttLib import TTFont
    chosen, total = fonts_for(contours_wanted)
    print(f"3. {total} glyph contours of {len(chosen)} fonts ({GLYPHS}), judged with --require cmrwi:")

    def through_pen():
        # Drawing first, then judging everything in one judge_many call.
        t_start = time.perf_counter()
        contours = []
        for path, names, _ in chosen:
            glyphs = TTFont(path).getGlyphSet()
            for n in names:
                contours.extend(cmr.fonttools.glyph_contours(glyphs, n))
        t_drawn = time.perf_counter()
        results = cmr.judge_many(contours, require="cmrwi")
        return results, t_drawn - t_start

    def through_queue():
        # Drawing and judging overlapped: batches of 256 contours go to a
        # cmr.JudgeQueue while the next glyphs are drawn (what
        # cmr.fonttools.check_glyphs does for one font).
        queue = cmr.JudgeQueue(require="cmrwi")
        batch = []
        for path, names, _ in chosen:
            glyphs = TTFont(path).getGlyphSet()
            for n in names:
                batch.extend(cmr.fonttools.glyph_contours(glyphs, n))
                if len(batch) >= 256:
                    queue.submit(batch)
                    batch = []
        queue.submit(batch)
        return queue.results()

    t0 = time.perf_counter()
    results, drawing = through_pen()
    py = time.perf_counter() - t0
    t0 = time.perf_counter()
    queued = through_queue()
    py_queue = time.perf_counter() - t0
    assert queued == results
    statuses = [r["status"] for r in results]
    with tempfile.TemporaryDirectory() as out:
        t0 = time.perf_counter()
        p = subprocess.run([CMR, "report", *[p for p, _, _ in chosen], "--glyphs", GLYPHS, "--require", "cmrwi",
                            "--no-thumbnails", "--no-severity", "--quiet", "--out", out], check=False, capture_output=True, text=True)
        cli = time.perf_counter() - t0
    print(f"   Python (fontTools + SplinePen + cmr.judge_many): {py:6.2f} s "
          f"(of which {drawing:.2f} s fontTools drawing through the pen, {py - drawing:.2f} s judging)")
    print(f"   cmr report --no-thumbnails --no-severity:        {cli:6.2f} s ({p.stdout.strip()})")
    print(f"   Python (the same through cmr.JudgeQueue):          {py_queue:6.2f} s (drawing and judging overlapped)")
    print(f"   ratio {py / cli:.2f} (judge_many after drawing), {py_queue / cli:.2f} (JudgeQueue); "
          f"judging alone {(py - drawing) / cli:.2f} ({len(results)} contours, {statuses.count('pass')} pass)")


if __name__ == "__main__":
    print(f"python_overhead.py: {machine()}")
    bench_analyze()
    bench_region()
    bench_pen()
