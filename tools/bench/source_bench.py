#!/usr/bin/python3
"""Benchmarks of font sources (issue 36 "Speed"; docs/fix.md, docs/report.md).

    source_bench.py CMR [OUT_DIR] [GATES] [--report-only]

1. A whole Latin UFO reported with the type gates, without fixes: UFOs of
   DejaVu Sans (TrueType: qcurve) and Nimbus Sans (CFF: curve) made by
   tools/make_test_ufo.py from U+0021..U+017F (about 330 glyphs each), then
   `cmr report UFO --glyphs all --require GATES --no-fixes --no-thumbnails
   --no-cache`
   (GATES: curvature-extrema-at-nodes,g2-at-smooth-nodes by default), wall
   time of the best of 3 and its CPU time (user + system), with severity (the
   default: every finding's smallest certified move, report/severity.hpp) and
   with --no-severity; the findings, and how many are info (severity below
   half a font unit).
2. A glyph's multi-gate on-grid fix: `cmr fix UFO --glyph G --require
   GATES --out TMP` for every glyph
   of A-Z a-z that fails, wall time and outcome each; the median and worst
   time, and how many were fixed; per fixed glyph its total squared move
   (the sum over moved points of the squared distance, font units) and
   whether each contour's fix was settled (docs/fix.md "On the grid"), and
   their sum (compare two binaries on the same glyphs with it).

--report-only: part 1 alone; --fix-only: part 2 alone. Each part prints the
load average (1, 5, 15 min) before and after it. Prints Markdown tables. Benchmarks, not tests: the numbers depend on the
machine (say which when quoting them).
"""
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

REPORT_ONLY = "--report-only" in sys.argv
FIX_ONLY = "--fix-only" in sys.argv
ARGV = [a for a in sys.argv if a not in ("--report-only", "--fix-only")]
CMR = os.path.abspath(ARGV[1]) if os.sep in ARGV[1] else ARGV[1]  # the runs' cwd is a scratch folder
HERE = os.path.dirname(os.path.abspath(__file__))
MAKE = os.path.join(HERE, "..", "make_test_ufo.py")
FONTS = {
    "DejaVu Sans": "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "Nimbus Sans": "/usr/share/fonts/opentype/urw-base35/NimbusSans-Regular.otf",
}
GATES = ARGV[3] if len(ARGV) > 3 else "curvature-extrema-at-nodes,g2-at-smooth-nodes"
LATIN = "".join(chr(c) for c in range(0x21, 0x180))
AZ = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"


def timed(args, cwd):
    t = time.perf_counter()
    r = subprocess.run([CMR, *args], cwd=cwd, capture_output=True, text=True)
    return time.perf_counter() - t, r


def cpu_of(args, cwd):
    """Wall and CPU seconds (user + system) of one run."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t, r = timed(args, cwd)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return t, after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime, r


def main():
    tmp = ARGV[2] if len(ARGV) > 2 else tempfile.mkdtemp(prefix="cmr-source-bench-")
    os.makedirs(tmp, exist_ok=True)
    if not FIX_ONLY:
        report_part(tmp)
    if not REPORT_ONLY:
        fix_part(tmp)


def load():
    return open("/proc/loadavg").read().split()[:3]


def report_part(tmp):
    print("## Report of a whole Latin UFO, type gates, no fixes (load before: %s)\n" % " ".join(load()))
    print("| font | glyphs | severity | best of 3 wall (s) | its CPU (s) | findings | info | glyphs failing |")
    print("|---|---|---|---|---|---|---|---|")
    for name, path in FONTS.items():
        ufo = os.path.join(tmp, name.replace(" ", "") + "-Latin.ufo")
        subprocess.run(["/usr/bin/python3", MAKE, path, ufo, LATIN], check=True)
        glyphs = len(os.listdir(os.path.join(ufo, "glyphs"))) - 1
        for mode, extra in (("on (default)", []), ("--no-severity", ["--no-severity"])):
            best, cpu, line = float("inf"), 0, ""
            out = os.path.join(tmp, "report")
            for k in range(3):
                # --no-cache: each run judges every glyph (a rerun into the
                # same folder would take them from its report.cache).
                t, c, r = cpu_of(["report", ufo, "--glyphs", "all", "--require", GATES, "--no-fixes", "--no-thumbnails",
                                  "--no-cache", "--quiet", "--out", out, *extra], tmp)
                if t < best:
                    best, cpu, line = t, c, r.stdout.strip()
            doc = json.load(open(os.path.join(out, "report.json")))
            findings = [f for sp in doc["splines"] for f in sp.get("findings", [])]
            info = sum(1 for f in findings if f.get("level") == "info")
            failing = line.split("glyphs, ", 1)[1].split(" failing")[0] if "glyphs, " in line else "?"
            print("| %s | %d | %s | %.2f | %.2f | %d | %d | %s |" % (name, glyphs, mode, best, cpu, len(findings), info,
                                                                 failing))
    print("\nload after: %s" % " ".join(load()))


def fix_part(tmp):
    print("\n## Multi-gate on-grid fix per failing glyph (A-Z a-z) (load before: %s)\n" % " ".join(load()))
    print("| font | failing glyphs | fixed | not fixed | median (s) | worst (s) | total squared move, fixed glyphs |")
    print("|---|---|---|---|---|---|---|")
    reasons = {}
    fixed_names = {}
    per_glyph = {}
    moves = {}
    for name, path in FONTS.items():
        ufo = os.path.join(tmp, name.replace(" ", "") + "-AZ.ufo")
        subprocess.run(["/usr/bin/python3", MAKE, path, ufo, AZ], check=True)
        times, fixed, failed, names = [], 0, 0, []
        for ch in AZ:
            glif = [f for f in os.listdir(os.path.join(ufo, "glyphs")) if f.endswith(".glif")]
            # the glyph's name: the file whose <unicode> is this character
            gname = None
            for f in glif:
                text = open(os.path.join(ufo, "glyphs", f)).read()
                if 'hex="%04X"' % ord(ch) in text:
                    gname = text.split('name="', 1)[1].split('"', 1)[0]
                    break
            if gname is None:
                continue
            out = os.path.join(tmp, "fixed.ufo")
            shutil.rmtree(out, ignore_errors=True)
            t, r = timed(["fix", ufo, "--glyph", gname, "--require", GATES, "--out", out], tmp)
            if r.returncode == 0 and '"already":false' not in r.stdout:
                continue  # passes as it is
            times.append(t)
            per_glyph.setdefault(name, []).append((t, gname))
            if r.returncode == 0:
                fixed += 1
                names.append(gname)
                doc = json.loads(r.stdout)
                squared = sum(m["distance"] ** 2 for c in doc["contours"] for m in c["moves"])
                settled = all(c.get("settled", True) for c in doc["contours"])
                moves.setdefault(name, []).append((gname, squared, settled))
            else:
                failed += 1
                why = r.stderr.strip().split(": ", 2)[-1][:90]
                reasons[why] = reasons.get(why, 0) + 1
        if times:
            print("| %s | %d | %d | %d | %.2f | %.2f | %.0f |" % (name, len(times), fixed, failed, statistics.median(times),
                                                                max(times), sum(q for _, q, _ in moves.get(name, []))))
            fixed_names[name] = names
    for name, names in fixed_names.items():
        print("\nFixed in %s: %s" % (name, " ".join(names) or "none"))
    for name, mv in moves.items():
        print("\nTotal squared move per fixed glyph in %s (* not settled in its time): %s" %
              (name, ", ".join("%s %.0f%s" % (g, q, "" if ok else "*") for g, q, ok in mv)))
    for name, tg in per_glyph.items():
        print("\nSeconds per glyph in %s, fastest first: %s" % (name, ", ".join("%s %.2f" % (g, t) for t, g in sorted(tg))))
    print("\nWhy not fixed (count, the reason's first words):\n")
    kinds = {}
    for why, n in reasons.items():
        key = why.split(": ", 1)[-1]
        key = key.split(" within")[0].split(" (")[0].split(";")[0]
        kinds[key] = kinds.get(key, 0) + n
    for why, n in sorted(kinds.items(), key=lambda kv: -kv[1]):
        print("- %d x %s" % (n, why))
    print("\nload after: %s" % " ".join(load()))


if __name__ == "__main__":
    main()
