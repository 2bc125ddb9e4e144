#!/usr/bin/python3
"""Benchmarks of font sources (issue 36 "Speed"; docs/fix.md, docs/report.md).

    source_bench.py CMR [OUT_DIR] [GATES]

1. A whole Latin UFO reported with the type gates, without fixes: UFOs of
   DejaVu Sans (TrueType: qcurve) and Nimbus Sans (CFF: curve) made by
   tools/make_test_ufo.py from U+0021..U+017F (about 330 glyphs each), then
   `cmr report UFO --glyphs all --require GATES --no-fixes --no-thumbnails`
   (GATES: curvature-extrema-at-nodes,g2-at-smooth-nodes by default), wall
   time of the best of 3.
2. A glyph's multi-gate on-grid fix: `cmr fix UFO --glyph G --require
   GATES --out TMP` for every glyph
   of A-Z a-z that fails, wall time and outcome each; the median and worst
   time, and how many were fixed.

Prints Markdown tables. Benchmarks, not tests: the numbers depend on the
machine (say which when quoting them).
"""
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

CMR = sys.argv[1]
HERE = os.path.dirname(os.path.abspath(__file__))
MAKE = os.path.join(HERE, "..", "make_test_ufo.py")
FONTS = {
    "DejaVu Sans": "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "Nimbus Sans": "/usr/share/fonts/opentype/urw-base35/NimbusSans-Regular.otf",
}
GATES = sys.argv[3] if len(sys.argv) > 3 else "curvature-extrema-at-nodes,g2-at-smooth-nodes"
LATIN = "".join(chr(c) for c in range(0x21, 0x180))
AZ = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"


def timed(args, cwd):
    t = time.perf_counter()
    r = subprocess.run([CMR, *args], cwd=cwd, capture_output=True, text=True)
    return time.perf_counter() - t, r


def main():
    tmp = sys.argv[2] if len(sys.argv) > 2 else tempfile.mkdtemp(prefix="cmr-source-bench-")
    os.makedirs(tmp, exist_ok=True)
    print("## Report of a whole Latin UFO, type gates, no fixes\n")
    print("| font | glyphs | best of 3 (s) | summary |")
    print("|---|---|---|---|")
    for name, path in FONTS.items():
        ufo = os.path.join(tmp, name.replace(" ", "") + "-Latin.ufo")
        subprocess.run(["/usr/bin/python3", MAKE, path, ufo, LATIN], check=True)
        best, line = float("inf"), ""
        for k in range(3):
            t, r = timed(["report", ufo, "--glyphs", "all", "--require", GATES, "--no-fixes", "--no-thumbnails",
                          "--quiet", "--out", os.path.join(tmp, "report-%d" % k)], tmp)
            best, line = min(best, t), r.stdout.strip()
        glyphs = len(os.listdir(os.path.join(ufo, "glyphs"))) - 1
        print("| %s | %d | %.2f | %s |" % (name, glyphs, best, line.split("; wrote")[0]))
    print("\n## Multi-gate on-grid fix per failing glyph (A-Z a-z)\n")
    print("| font | failing glyphs | fixed | not fixed | median (s) | worst (s) |")
    print("|---|---|---|---|---|---|")
    reasons = {}
    fixed_names = {}
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
            if r.returncode == 0:
                fixed += 1
                names.append(gname)
            else:
                failed += 1
                why = r.stderr.strip().split(": ", 2)[-1][:90]
                reasons[why] = reasons.get(why, 0) + 1
        if times:
            print("| %s | %d | %d | %d | %.2f | %.2f |" % (name, len(times), fixed, failed, statistics.median(times),
                                                          max(times)))
            fixed_names[name] = names
    for name, names in fixed_names.items():
        print("\nFixed in %s: %s" % (name, " ".join(names) or "none"))
    print("\nWhy not fixed (count, the reason's first words):\n")
    kinds = {}
    for why, n in reasons.items():
        key = why.split(": ", 1)[-1]
        key = key.split(" within")[0].split(" (")[0].split(";")[0]
        kinds[key] = kinds.get(key, 0) + n
    for why, n in sorted(kinds.items(), key=lambda kv: -kv[1]):
        print("- %d x %s" % (n, why))


if __name__ == "__main__":
    main()
