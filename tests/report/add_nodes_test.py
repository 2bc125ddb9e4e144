#!/usr/bin/python3
"""`cmr fix FONT.ufo --glyph G --require ... --add-nodes` (report/glyph_nodes.hpp)
end to end, on URW Gothic Book's `b` (tools/make_test_ufo.py): its counter's
five segments each have a curvature peak between their nodes, and no move of
the points passes the two type gates; with a node added at each peak, the
fix passes.

    add_nodes_test.py SOURCE_DIR CMR

Checked independently of cmr: the exact judge (exact_glif_check.py,
rational arithmetic) fails the source and passes the written glyph; the
written .glif differs from the source only in <point> lines (x/y of moved
points, integers) and the added <point> lines, three per added node, each
added node smooth="yes" and exactly smooth (its handles collinear with it
in integers, on either side); every other file of the UFO is byte for byte
the source's. Then Nimbus Sans `D`: both bowls meet the stem square, a
node at the middle of each cubic of those line joins does not let any
move pass g2 there, and two nodes (at 1/3 and 2/3) do: the fix adds four
a contour, at those parameters, and the exact judge passes it. Prints "N
passed, M failed" and exits 1 on any failure.
"""
import filecmp
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from glif_checks import Checks  # noqa: E402

SRC, CMR = sys.argv[1], sys.argv[2]
GOTHIC = "/usr/share/fonts/opentype/urw-base35/URWGothic-Book.otf"
NIMBUS = "/usr/share/fonts/opentype/urw-base35/NimbusSans-Regular.otf"
GATES = "curvature-extrema-at-nodes,g2-at-smooth-nodes"
PY = "/usr/bin/python3"
check = Checks()


def run(*args, cwd=None):
    return subprocess.run([CMR, *args], cwd=cwd, capture_output=True, text=True, timeout=600)


def points(path):
    """Per contour, its <point> lines' attributes, in order."""
    out, cur = [], None
    for line in open(path).read().split("\n"):
        if "<contour" in line:
            cur = []
        elif "</contour>" in line:
            out.append(cur)
            cur = None
        elif "<point" in line and cur is not None:
            cur.append(dict(re.findall(r'(\w+)=["\']([^"\']*)["\']', line)))
    return out


def lines_only_points(src, fix):
    """The fixed .glif's lines are the source's, but for <point> lines (moved or added)."""
    a = [x for x in open(src).read().split("\n") if "<point" not in x]
    b = [x for x in open(fix).read().split("\n") if "<point" not in x]
    return a == b


def main():
    tmp = tempfile.mkdtemp(prefix="cmr-nodes-")
    try:
        ufo = os.path.join(tmp, "Gothic.ufo")
        subprocess.run([PY, os.path.join(SRC, "tools/make_test_ufo.py"), GOTHIC, ufo, "b"], check=True)
        src = os.path.join(ufo, "glyphs", "b.glif")
        judge = [PY, os.path.join(SRC, "tests/report/exact_glif_check.py")]

        r = run("fix", "Gothic.ufo", "--glyph", "b", "--require", GATES, "--out", "Moves.ufo", cwd=tmp)
        check("without --add-nodes: no fix (exit 2, one line), nothing written",
              r.returncode == 2 and r.stderr.count("\n") == 1 and "no certified fix" in r.stderr
              and not os.path.exists(os.path.join(tmp, "Moves.ufo")), r.stderr)

        r = run("fix", "Gothic.ufo", "--glyph", "b", "--require", GATES, "--add-nodes", "--out", "Nodes.ufo", cwd=tmp)
        check("--add-nodes: exit 0", r.returncode == 0, r.stderr)
        fix = os.path.join(tmp, "Nodes.ufo", "glyphs", "b.glif")
        if r.returncode == 0:
            doc = json.loads(r.stdout)
            added = [n for c in doc["contours"] for n in c.get("added_nodes", [])]
            check("five nodes added, each at a curvature extremum of the counter",
                  len(added) == 5 and all(n["why"] == "a curvature extremum" and n["point"].startswith("b/c1/p")
                                          for n in added), added)
            check("the exact judge fails the source and passes the fix",
                  subprocess.run(judge + [src], capture_output=True).returncode == 1
                  and subprocess.run(judge + [fix], capture_output=True).returncode == 0,
                  subprocess.run(judge + [fix], capture_output=True, text=True).stdout)
            check("only <point> lines differ", lines_only_points(src, fix))
            ps, pf = points(src), points(fix)
            check("three points added per node, in the counter only",
                  len(pf[0]) == len(ps[0]) and len(pf[1]) == len(ps[1]) + 15, [len(c) for c in pf])
            check("every coordinate an integer",
                  all(re.fullmatch(r"-?\d+", p[k]) for c in pf for p in c for k in ("x", "y")))
            ok = True
            for n in added:
                k = int(n["point"].rsplit("p", 1)[1])
                c = pf[1]
                p, q, s = c[k - 1], c[k], c[(k + 1) % len(c)]
                ax, ay = int(q["x"]) - int(p["x"]), int(q["y"]) - int(p["y"])
                bx, by = int(s["x"]) - int(q["x"]), int(s["y"]) - int(q["y"])
                ok = ok and q.get("type") == "curve" and q.get("smooth") == "yes" and "type" not in p \
                    and "type" not in s and ax * by == ay * bx and ax * bx + ay * by > 0 \
                    and [int(q["x"]), int(q["y"])] == n["at"]
            check("each added node is where the document says, smooth=yes and exactly smooth", ok, added)
            same = all(filecmp.cmp(os.path.join(d, f), os.path.join(tmp, "Nodes.ufo", os.path.relpath(d, ufo), f),
                                   shallow=False)
                       for d, _, files in os.walk(ufo) for f in files if f != "b.glif")
            check("every other file of the UFO is the source's, byte for byte", same)

            copy = os.path.join(tmp, "InPlace.ufo")
            shutil.copytree(ufo, copy)
            r2 = run("fix", "InPlace.ufo", "--glyph", "b", "--require", GATES, "--add-nodes", "--in-place", cwd=tmp)
            check("--in-place writes the same glyph as --out",
                  r2.returncode == 0 and filecmp.cmp(os.path.join(copy, "glyphs", "b.glif"), fix, shallow=False),
                  r2.stderr)
            r3 = run("fix", "Gothic.ufo", "--glyphs", "b", "--require", GATES, "--add-nodes", "--out", "All.ufo",
                     cwd=tmp)
            check("--glyphs: the same glyph as --glyph",
                  r3.returncode == 0 and filecmp.cmp(os.path.join(tmp, "All.ufo", "glyphs", "b.glif"), fix,
                                                     shallow=False), r3.stderr)

        # Line joins: two nodes where one is not enough.
        nimbus = os.path.join(tmp, "Nimbus.ufo")
        subprocess.run([PY, os.path.join(SRC, "tools/make_test_ufo.py"), NIMBUS, nimbus, "D"], check=True)
        r = run("fix", "Nimbus.ufo", "--glyph", "D", "--require", GATES, "--add-nodes", "--out", "NimbusD.ufo", cwd=tmp)
        check("Nimbus Sans D --add-nodes: exit 0", r.returncode == 0, r.stderr)
        if r.returncode == 0:
            doc = json.loads(r.stdout)
            ts = [sorted(round(n["t"], 6) for n in c.get("added_nodes", [])) for c in doc["contours"]]
            check("two nodes, at 1/3 and 2/3, in each cubic of the two line joins of each bowl",
                  ts == [[0.333333, 0.333333, 0.666667, 0.666667]] * 2
                  and all(n["why"] == "a line's smooth join" for c in doc["contours"] for n in c["added_nodes"]), ts)
            src_d = os.path.join(nimbus, "glyphs", "D_.glif")
            fix_d = os.path.join(tmp, "NimbusD.ufo", "glyphs", "D_.glif")
            check("Nimbus Sans D: the exact judge fails the source and passes the fix",
                  subprocess.run(judge + [src_d], capture_output=True).returncode == 1
                  and subprocess.run(judge + [fix_d], capture_output=True).returncode == 0)
            check("Nimbus Sans D: only <point> lines differ, integers",
                  lines_only_points(src_d, fix_d)
                  and all(re.fullmatch(r"-?\d+", p[k]) for c in points(fix_d) for p in c for k in ("x", "y")))

        # Bad requests: one line, exit 2, nothing written.
        for args, what in ((["--grid", "0"], "needs the grid"),
                           (["--points", "b/c1/p1"], "with --points"),):
            r = run("fix", "Gothic.ufo", "--glyph", "b", "--require", GATES, "--add-nodes", *args, "--out", "Bad.ufo",
                    cwd=tmp)
            check("--add-nodes %s: exit 2, one line naming --add-nodes, nothing written" % " ".join(args),
                  r.returncode == 2 and r.stderr.count("\n") == 1 and "--add-nodes" in r.stderr and what in r.stderr
                  and not os.path.exists(os.path.join(tmp, "Bad.ufo")), r.stderr)
        spline = os.path.join(tmp, "s.json")
        with open(spline, "w") as f:
            json.dump({"degree": 3, "points": [[0, 0], [1, 2], [3, 2], [4, 0]], "knots": [0, 0, 0, 1, 1, 1]}, f)
        r = run("fix", "s.json", "--require", "cmr", "--add-nodes", cwd=tmp)
        check("--add-nodes on a spline file: exit 2, one line", r.returncode == 2 and r.stderr.count("\n") == 1
              and "--add-nodes: for UFO sources" in r.stderr, r.stderr)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    check.exit()


if __name__ == "__main__":
    main()
