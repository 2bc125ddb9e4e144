#!/usr/bin/python3
"""Random glyphs judged and fixed by cmr, held to an exact judge written independently of it.

    random_glyphs_test.py SOURCE_DIR CMR [FIRST_SEED COUNT [WORK]]

Each seed draws a plausible glyph (Python's random, so the same glyph on every
machine): one or two closed contours around ellipses, integer points, either
cubic (`curve`, smooth nodes with exactly collinear handles, some straight
`line` pieces) or TrueType-flavoured (`qcurve` with one or two off-curve
points, so implied on-curve midpoints), and writes it as a UFO with
ufoLib2 (Debian's python3-ufolib2). The seed picks the gates:
curvature-extrema-at-nodes, g2-at-smooth-nodes, or both. Then:

 * `cmr report` (every finding failing: --no-severity) must pass or fail
   each contour on each gate exactly where tests/report/exact_glif_check.py
   (rational arithmetic, no cmr code) does, and every fix its report.json
   claims (certified_fixes), applied by the moved points' names, must make
   that contour pass the fix's checks under the exact judge;
 * `cmr fix --glyph a --require GATES --work WORK --out FIXED.ufo` either
   exits 0, and then the exact judge passes the written glyph on the gates
   and only `<point>` x/y changed, to integers (glif_checks.py; a glyph that
   passes already is written back byte for byte), or exits 2
   with one line on stderr and writes nothing.

Fixes that the search does not find within WORK are allowed (most random
shapes have smooth nodes where the curvature changes sign, which no move
passes); the run must still fix at least MIN_FIXED of the glyphs, so that it
cannot pass by fixing none (7 of the 24 default seeds are fixed at 300,000
units; the glyph's time guard, in proportion to its work, 1.4 s of CPU here,
can end a slower build's searches sooner, so the floor is lower, and a
sanitizer build, CMR_SANITIZER_BUILD=1 from tests/CMakeLists.txt, has none).
A campaign of 120 seeds at the default work (docs/fix.md, "Random glyphs,
held to the exact judge") found no disagreement.
"""
import json
import math
import os
import random
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from glif_checks import only_xy_changed  # noqa: E402

PY = "/usr/bin/python3"  # Debian's: ufoLib2 and fontTools live there
GATES = ["curvature-extrema-at-nodes", "g2-at-smooth-nodes", "curvature-extrema-at-nodes,g2-at-smooth-nodes"]
CHECKER_GATES = {"curvature-extrema-at-nodes": "extrema", "g2-at-smooth-nodes": "g2"}
MIN_FIXED = 3
failures = []


def check(name, ok, detail=""):
    print(("ok   " if ok else "FAIL ") + name + ("" if ok else ": " + detail))
    if not ok:
        failures.append(name)


def cubic_contour(pen, rnd, cx, cy, rx, ry, n, reverse):
    """Nodes near an ellipse, each with a small integer tangent direction; a node after a line is a corner."""
    nodes = []
    for a in sorted(rnd.uniform(0, 2 * math.pi) for _ in range(n)):
        x, y = round(cx + rx * math.cos(a) + rnd.randint(-15, 15)), round(cy + ry * math.sin(a) + rnd.randint(-15, 15))
        tx, ty = -rx * math.sin(a), ry * math.cos(a)
        s, k = max(abs(tx), abs(ty)), rnd.choice([1, 2, 3, 5])
        dx, dy = round(tx / s * k + rnd.uniform(-0.4, 0.4)), round(ty / s * k + rnd.uniform(-0.4, 0.4))
        nodes.append((x, y, dx or (0 if dy else 1), dy))
    if reverse:
        nodes = [(x, y, -dx, -dy) for x, y, dx, dy in nodes[::-1]]
    line_before = [rnd.random() < 0.15 for _ in nodes]
    pen.beginPath()
    for i, (x, y, dx, dy) in enumerate(nodes):
        if line_before[i]:
            pen.addPoint((x, y), segmentType="line", smooth=False)
            continue
        px, py, pdx, pdy = nodes[i - 1]
        length = math.hypot(x - px, y - py)
        u = max(1, round(length * rnd.uniform(0.2, 0.45) / math.hypot(pdx, pdy)))
        v = max(1, round(length * rnd.uniform(0.2, 0.45) / math.hypot(dx, dy)))
        pen.addPoint((px + u * pdx, py + u * pdy))  # on the previous node's tangent: smooth there exactly
        pen.addPoint((x - v * dx, y - v * dy))
        smooth = not line_before[(i + 1) % len(nodes)] and rnd.random() < 0.85
        pen.addPoint((x, y), segmentType="curve", smooth=smooth)
    pen.endPath()


def quadratic_contour(pen, rnd, cx, cy, rx, ry, n, reverse):
    """On-curve points on an ellipse with one or two off-curve points before each (implied midpoints between two)."""
    angles = sorted(rnd.uniform(0, 2 * math.pi) for _ in range(n))
    if reverse:
        angles = angles[::-1]
    pen.beginPath()
    for a in angles:
        k = rnd.choice([1, 2])
        for j in range(k):
            b = a - (k - j) * 0.5 * (2 * math.pi / n) / (k + 1) * (-1 if reverse else 1)
            pen.addPoint((round(cx + 1.1 * rx * math.cos(b) + rnd.randint(-20, 20)),
                          round(cy + 1.1 * ry * math.sin(b) + rnd.randint(-20, 20))))
        pen.addPoint((round(cx + rx * math.cos(a)), round(cy + ry * math.sin(a))), segmentType="qcurve",
                     smooth=rnd.random() < 0.3)
    pen.endPath()


def make_glyph(seed, quadratic, path):
    import ufoLib2
    rnd = random.Random(seed)
    font = ufoLib2.Font()
    font.info.unitsPerEm = 1000
    glyph = font.newGlyph("a")
    glyph.width = 600
    contour = quadratic_contour if quadratic else cubic_contour
    contour(glyph.getPointPen(), rnd, 300, 350, rnd.randint(150, 300), rnd.randint(150, 350), rnd.randint(4, 8), False)
    if rnd.random() < 0.4:
        contour(glyph.getPointPen(), rnd, 300, 350, rnd.randint(60, 120), rnd.randint(60, 150), rnd.randint(4, 6),
                True)
    font.save(path, overwrite=True)


def exact_judge(src, glif, gate):
    """Contour indices the independent judge fails on `gate`."""
    r = subprocess.run([PY, os.path.join(src, "tests/report/exact_glif_check.py"), glif, "--gates",
                        CHECKER_GATES[gate]], capture_output=True, text=True)
    failed = {int(line.split()[0][1:]) for line in r.stdout.splitlines() if line.startswith("c")}
    # Exit 1 with a violation named, or 0 with none; anything else (a Python error exits 1 too) is not a verdict.
    if r.stderr or r.returncode != (1 if failed else 0):
        raise RuntimeError("exact_glif_check.py %s: exit %d: %s" % (glif, r.returncode, r.stderr.strip()))
    return failed


def claimed_fixes(src, what, report, glif, gates, scratch):
    """Every fix the report claims (certified_fixes), applied to the source's points by their names
    (glyph/cK/pJ: contour K, the .glif's point J), must make that contour pass its checks exactly."""
    for spline in report["splines"]:
        for f in spline.get("certified_fixes") or []:
            if not f["found"]:
                continue
            checks = gates.split(",") if f["check"].startswith("all:") else [f["check"].split(":")[0]]
            tree = ET.parse(glif)
            contours = list(tree.getroot().iter("contour"))
            names_ok = True
            for m in f["moves"]:
                glyph, contour, point = m["name"].split("/")
                names_ok = names_ok and contour[0] == "c" and point[0] == "p" and point[1:].isdigit()
                if not names_ok:
                    break
                p = list(contours[int(contour[1:])].iter("point"))[int(point[1:])]
                p.set("x", "%g" % m["to"][0])
                p.set("y", "%g" % m["to"][1])
            if not names_ok:
                check("report %s: %s's claimed fix names only source points" % (what, spline["name"]), False,
                      str([m["name"] for m in f["moves"]]))
                continue
            tree.write(scratch)
            left = {g: spline["contour"] in exact_judge(src, scratch, g) for g in checks}
            check("report %s: %s's claimed fix of %s passes the exact judge" % (what, spline["name"], f["check"]),
                  not any(left.values()), str(left))


def main():
    src, cmr = sys.argv[1], sys.argv[2]
    first = int(sys.argv[3]) if len(sys.argv) > 3 else 0
    count = int(sys.argv[4]) if len(sys.argv) > 4 else 24
    work = sys.argv[5] if len(sys.argv) > 5 else "300000"
    fixed = unfixed = passing = 0
    with tempfile.TemporaryDirectory() as tmp:
        for seed in range(first, first + count):
            quadratic = seed % 2 == 1
            gates = GATES[seed // 2 % 3]
            what = "seed %d (%s, %s)" % (seed, "qcurve" if quadratic else "curve", gates)
            ufo = os.path.join(tmp, "s%d.ufo" % seed)
            make_glyph(seed, quadratic, ufo)
            glif = os.path.join(ufo, "glyphs", "a.glif")
            out = os.path.join(tmp, "r%d" % seed)
            r = subprocess.run([cmr, "report", ufo, "--glyphs", "all", "--require", gates, "--no-severity", "--out",
                                out], capture_output=True, text=True)
            if r.returncode not in (0, 1):
                check("report " + what, False, r.stderr.strip())
                continue
            report = json.load(open(os.path.join(out, "report.json")))
            for gate in gates.split(","):
                by_cmr = {s["contour"] for s in report["splines"]
                          for g in s.get("gates") or [] if g["gate"].split(":")[0] == gate and not g["pass"]}
                by_exact = exact_judge(src, glif, gate)
                check("report %s: %s fails the contours the exact judge fails" % (what, gate), by_cmr == by_exact,
                      "cmr %s, exact %s" % (sorted(by_cmr), sorted(by_exact)))
            claimed_fixes(src, what, report, glif, gates, os.path.join(tmp, "claimed.glif"))
            failing = any(exact_judge(src, glif, g) for g in gates.split(","))
            fix = os.path.join(tmp, "f%d.ufo" % seed)
            f = subprocess.run([cmr, "fix", ufo, "--glyph", "a", "--require", gates, "--work", work, "--out", fix],
                               capture_output=True, text=True)
            passing += not failing
            if f.returncode == 2:
                unfixed += 1
                lines = f.stderr.strip().splitlines()
                check("fix %s: no fix, one line and nothing written" % what,
                      failing and len(lines) == 1 and not os.path.exists(fix), f.stderr.strip())
                continue
            if f.returncode != 0:
                check("fix " + what, False, "exit %d: %s" % (f.returncode, f.stderr.strip()))
                continue
            fixed_glif = os.path.join(fix, "glyphs", "a.glif")
            # A glyph that passes already is written back unchanged.
            moved, why = only_xy_changed(glif, fixed_glif) if failing else (
                open(glif, "rb").read() == open(fixed_glif, "rb").read(), "the passing glyph changed")
            left = {g: exact_judge(src, fixed_glif, g) for g in gates.split(",")}
            check("fix %s: only x/y change, to integers, and the exact judge passes every gate" % what,
                  moved and not any(left.values()), "%s, left %s" % (why, left))
            fixed += failing
            for name in os.listdir(ufo):  # every other file byte for byte
                if name != "glyphs" and os.path.isfile(os.path.join(ufo, name)):
                    check("fix %s: %s unchanged" % (what, name),
                          open(os.path.join(ufo, name), "rb").read() == open(os.path.join(fix, name), "rb").read())
    print("%d glyphs: %d fixed, %d not fixed, %d passing already" % (count, fixed, unfixed, passing))
    if not os.environ.get("CMR_SANITIZER_BUILD"):
        check("at least %d of the failing glyphs fixed (%d)" % (MIN_FIXED, fixed), fixed >= MIN_FIXED)
    print("%d failure(s)" % len(failures))
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
