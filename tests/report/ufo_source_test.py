#!/usr/bin/python3
"""Font sources end to end: a UFO made from Nimbus Sans (CFF: cubic `curve`
contours) and one from DejaVu Sans (TrueType: `qcurve` contours) by
tools/make_test_ufo.py, then `cmr report`, `cmr import` and `cmr fix` on
them, and malformed sources.

    ufo_source_test.py SOURCE_DIR CMR

Prints "N passed, M failed" and exits 1 on any failure.
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
from glif_checks import only_xy_changed  # noqa: E402

SRC, CMR = sys.argv[1], sys.argv[2]
PY = "/usr/bin/python3"
NIMBUS = "/usr/share/fonts/opentype/urw-base35/NimbusSans-Regular.otf"
DEJAVU = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"
results = []


def check(name, ok, detail=""):
    results.append(bool(ok))
    print(("PASS " if ok else "FAIL ") + name + ("" if ok else ": " + detail))


# A sanitizer build (tools/sanitize.sh) runs several times slower than the
# Release build that the default fix budget (20 s) is set for.
SLOW_BUILD_BUDGET = ["--fix-budget", "400"] if os.environ.get("CMR_SANITIZER_BUILD") == "1" else []


def run(*args, cwd=None):
    return subprocess.run([CMR, *args], cwd=cwd, capture_output=True, text=True, timeout=300)


def tree_files(root):
    out = []
    for d, _, files in os.walk(root):
        out += [os.path.relpath(os.path.join(d, f), root) for f in files]
    return sorted(out)


def exact_judge(path, gates):
    """tests/report/exact_glif_check.py: the gates judged in rational arithmetic, independently of cmr."""
    return subprocess.run([PY, os.path.join(SRC, "tests/report/exact_glif_check.py"), path, "--gates", gates],
                          capture_output=True, text=True)


def fixed_glyph(tmp, font, glyph, glif, require, out, gates, what):
    """`cmr fix FONT --glyph G --require R --out OUT` exits 0, changes only x/y of moved points (to
    integers), and the independent exact check fails the source's glyph on `gates` and passes the
    fix's. Returns (source .glif, fixed .glif), or None where the fix failed."""
    r = run("fix", os.path.basename(font), "--glyph", glyph, "--require", require, "--out", out, cwd=tmp)
    check("fix %s exits 0" % what, r.returncode == 0, r.stderr)
    if r.returncode != 0:
        return None
    src, fix = os.path.join(font, "glyphs", glif), os.path.join(tmp, out, "glyphs", glif)
    ok, why = only_xy_changed(src, fix)
    check("%s: only x/y of moved points change, to integers" % what, ok, why)
    before, after = exact_judge(src, gates), exact_judge(fix, gates)
    check("exact judge (%s): %s fails, the fixed glyph passes" % (gates, what),
          before.returncode == 1 and after.returncode == 0, before.stdout[:200] + after.stdout)
    return src, fix


def main():
    tmp = tempfile.mkdtemp(prefix="cmr-ufo-")
    try:
        nimbus = os.path.join(tmp, "Nimbus.ufo")
        dejavu = os.path.join(tmp, "DejaVu.ufo")
        subprocess.run([PY, os.path.join(SRC, "tools/make_test_ufo.py"), NIMBUS, nimbus], check=True)
        subprocess.run([PY, os.path.join(SRC, "tools/make_test_ufo.py"), DEJAVU, dejavu], check=True)

        # report: SARIF results on the .glif's <point> lines
        r = run("report", "Nimbus.ufo", "--require", "extrema-at-nodes,g2-at-smooth-nodes", "--out", "r",
                "--sarif", "r.sarif", "--no-thumbnails", "--quiet", cwd=tmp)
        check("report exits 1 on findings", r.returncode == 1, r.stderr)
        sarif = json.load(open(os.path.join(tmp, "r.sarif")))
        res = sarif["runs"][0]["results"]
        on_point = 0
        for x in res:
            loc = x["locations"][0]["physicalLocation"]
            uri, line = loc["artifactLocation"]["uri"], loc.get("region", {}).get("startLine", 0)
            path = uri[len("file://"):] if uri.startswith("file://") else os.path.join(tmp, uri)
            if uri.endswith(".glif") and line > 0 and "<point" in open(path).read().split("\n")[line - 1]:
                on_point += 1
        check("every SARIF finding on its <point> line", len(res) > 0 and on_point == len(res),
              "%d of %d" % (on_point, len(res)))
        pages = "".join(open(os.path.join(tmp, "r", f)).read() for f in os.listdir(os.path.join(tmp, "r"))
                        if f.endswith(".html"))
        m = re.search(r"<code>(cmr fix Nimbus\.ufo --glyph o --require [^<]*) --in-place</code>", pages)
        check("the page prints the command that writes a glyph's fix back", m is not None)
        if m:
            r = run(*m.group(1).split()[1:], "--out", "FromPage.ufo", cwd=tmp)
            check("the page's command runs", r.returncode == 0, r.stderr)
        # the page's and the Markdown's commands name only checks a point move can fix: cmr fix refuses g3
        # (and no move passes xy-extrema-at-nodes); a glyph failing only those gets no command
        r = run("report", "Nimbus.ufo", "--glyphs", "O,o", "--require", "g3-at-smooth-nodes,curvature-extrema-at-nodes",
                "--out", "rg3", "--no-thumbnails", "--quiet", "--fix-budget", "0", "--markdown", "rg3.md", cwd=tmp)
        pages = "".join(open(os.path.join(tmp, "rg3", f)).read() for f in os.listdir(os.path.join(tmp, "rg3"))
                        if f.endswith(".html")) if r.returncode == 1 else ""
        cmds = re.findall(r"<code>(cmr fix Nimbus\.ufo --glyph \w+ --require [^<]*) --in-place</code>", pages)
        check("with g3 required, the page's commands leave g3 out",
              cmds and all(c.endswith("--require curvature-extrema-at-nodes") for c in cmds), str(cmds) + r.stderr)
        if cmds:
            r = run(*cmds[0].split()[1:], "--out", "FromPageG3.ufo", cwd=tmp)
            check("the page's command without g3 runs", r.returncode == 0, r.stderr)
        md = open(os.path.join(tmp, "rg3.md")).read() if os.path.exists(os.path.join(tmp, "rg3.md")) else ""
        m = re.search(r"fix on the grid: <code>(cmr fix Nimbus\.ufo --glyphs all --require ([^ <]*) --in-place)</code>", md)
        check("the Markdown gives a failing font source the whole-font command, without g3",
              m is not None and m.group(2) == "curvature-extrema-at-nodes", md[:1500])
        if m:
            r = run(*m.group(1).replace("--glyphs all", "--glyphs o").replace("--in-place", "--out FromMd.ufo").split()[1:],
                    cwd=tmp)
            check("the Markdown's command runs (for o)", r.returncode == 0, r.stderr)
        for opt, says in ((["--strict"], "--glyphs all --strict --require"),
                          (["--min-severity", "2"], "--glyphs all --min-severity 2 --require"),
                          (["--no-severity"], "--glyphs all --strict --require")):
            r = run("report", "Nimbus.ufo", "--glyphs", "o", "--require", "curvature-extrema-at-nodes", *opt, "--out",
                    "rsv", "--no-thumbnails", "--quiet", "--fix-budget", "0", "--markdown", "rsv.md", cwd=tmp)
            md = open(os.path.join(tmp, "rsv.md")).read() if r.returncode == 1 else ""
            check("the Markdown's whole-font command keeps the run's severity rule (%s)" % " ".join(opt), says in md, md[:800])
            shutil.rmtree(os.path.join(tmp, "rsv"), ignore_errors=True)
        # e and r fail g3 (no point-move fix); their g2 jumps are info (a move below half a unit): the
        # Markdown has no cmr fix command for them, since it would find nothing to fix
        r = run("report", "Nimbus.ufo", "--glyphs", "e,r", "--require", "g3-at-smooth-nodes,g2-at-smooth-nodes",
                "--out", "rg3info", "--no-thumbnails", "--quiet", "--fix-budget", "0", "--markdown", "rg3info.md", cwd=tmp)
        md = open(os.path.join(tmp, "rg3info.md")).read() if r.returncode == 1 else "cmr fix"
        check("g3 failing and only info g2 findings: no cmr fix command in the Markdown", "cmr fix" not in md, md[:600])
        r = run("report", "Nimbus.ufo", "--glyphs", "O,o", "--require", "g3-at-smooth-nodes", "--out", "rg3only",
                "--no-thumbnails", "--quiet", "--fix-budget", "0", "--markdown", "rg3only.md", cwd=tmp)
        pages = "".join(open(os.path.join(tmp, "rg3only", f)).read() for f in os.listdir(os.path.join(tmp, "rg3only"))
                        if f.endswith(".html")) if r.returncode == 1 else "<code>cmr fix"
        check("only g3 required: neither the page nor the Markdown prints a cmr fix command",
              "<code>cmr fix" not in pages and "cmr fix" not in open(os.path.join(tmp, "rg3only.md")).read(), r.stderr)
        # severity: the smallest certified move that removes each finding
        r = run("report", "Nimbus.ufo", "--glyphs", "O,o", "--require", "curvature-extrema-at-nodes,g2-at-smooth-nodes",
                "--min-severity", "0.5", "--out", "rs", "--sarif", "rs.sarif", "--no-thumbnails", "--quiet", cwd=tmp)
        doc = json.load(open(os.path.join(tmp, "rs", "report.json"))) if r.returncode in (0, 1) else {"splines": []}
        found = [f for s in doc["splines"] for f in s.get("findings", [])]
        check("--min-severity: every finding has a severity and a level", found and all(
            "severity" in f and f["level"] in ("info", "error") for f in found), str(found[:2]))
        check("severity is a move in font units (positive, finite where a fix was found)",
              all(f["severity"] is None or f["severity"] > 0 for f in found) and any(f["severity"] for f in found))
        check("a finding without a severity says why (severity_note) and is an error, never info",
              all((f["severity"] is None) == ("severity_note" in f) and
                  (f["severity"] is not None or (f["level"] == "error" and
                                                 f["severity_note"] in ("no allowed move", "none found")))
                  for f in found), str([f for f in found if f["severity"] is None][:2]))
        index = open(os.path.join(tmp, "rs", "index.html")).read() if os.path.exists(os.path.join(tmp, "rs", "index.html")) else ""
        ranked = [float(x) for x in re.findall(r"\(([0-9.]+) units; \d+\)", index)]
        # Each severity comes from a fix search of 2 s a contour (kReportFixSeconds);
        # a sanitizer build (about 10 times slower) may find one glyph's only: there
        # the order of those found is checked, in Release both glyphs'.
        sanitized = os.environ.get("CMR_SANITIZER_BUILD") == "1"
        check("the overview ranks glyphs by severity",
              (len(ranked) >= 1 if sanitized else len(ranked) == 2) and ranked == sorted(ranked, reverse=True),
              str(ranked))
        r = run("report", "Nimbus.ufo", "--glyphs", "O,o", "--require", "curvature-extrema-at-nodes,g2-at-smooth-nodes",
                "--min-severity", "1000", "--out", "rs2", "--sarif", "rs2.sarif", "--no-thumbnails", "--quiet", cwd=tmp)
        levels = {x["level"] for x in json.load(open(os.path.join(tmp, "rs2.sarif")))["runs"][0]["results"]}
        finite = all(f["severity"] is not None and f["severity"] < 1000 for f in found)
        check("findings below --min-severity are info: they pass, SARIF level note",
              (r.returncode == 0 and levels == {"note"}) if finite else r.returncode == 1, r.stdout + str(levels))
        r = run("report", "Nimbus.ufo", "--glyphs", "O,o", "--require", "curvature-extrema-at-nodes,g2-at-smooth-nodes",
                "--min-severity", "1000", "--strict", "--out", "rs3", "--no-thumbnails", "--quiet", cwd=tmp)
        check("--strict: info findings fail too", r.returncode == 1, r.stdout)
        r = run("report", "Nimbus.ufo", "--strict", "--no-severity", "--out", "rs4", cwd=tmp)
        check("--strict with --no-severity: exit 2", r.returncode == 2 and "--strict" in r.stderr, r.stderr)
        # severity is on by default for fonts (threshold 0.5), off with --no-severity
        r = run("report", "Nimbus.ufo", "--glyphs", "O,o", "--require", "curvature-extrema-at-nodes,g2-at-smooth-nodes",
                "--out", "rs5", "--no-thumbnails", "--quiet", cwd=tmp)
        default = [f for s in json.load(open(os.path.join(tmp, "rs5", "report.json")))["splines"]
                   for f in s.get("findings", [])] if r.returncode in (0, 1) else []
        check("by default a font's findings have their severity (as --min-severity 0.5)",
              default and len(default) == len(found) and all(
                  "severity" in f and f["level"] in ("info", "error") for f in default), str(default[:2]))
        r = run("report", "Nimbus.ufo", "--glyphs", "O,o", "--require", "curvature-extrema-at-nodes,g2-at-smooth-nodes",
                "--no-severity", "--out", "rs6", "--no-thumbnails", "--quiet", cwd=tmp)
        plain = [f for s in json.load(open(os.path.join(tmp, "rs6", "report.json")))["splines"]
                 for f in s.get("findings", [])] if r.returncode in (0, 1) else []
        check("--no-severity: no severity, every finding an error", plain and r.returncode == 1 and all(
            "severity" not in f and f.get("level", "error") == "error" for f in plain), str(plain[:2]))

        r = run("report", "DejaVu.ufo", "--glyphs", "all", "--out", "r2", "--no-thumbnails", "--quiet", cwd=tmp)
        check("a TrueType-flavoured (qcurve) UFO reports every glyph", r.returncode in (0, 1) and "52 glyphs" in r.stdout,
              r.stdout + r.stderr)

        # import: names in the .glif's own order
        r = run("import", "Nimbus.ufo", "--glyphs", "O", "--out", "imp", cwd=tmp)
        names = json.load(open(os.path.join(tmp, "imp", "O_c0.json")))["point_names"] if r.returncode == 0 else []
        check("import names points GLYPH/cC/pP", names[:3] == ["O/c0/p0", "O/c0/p1", "O/c0/p2"], str(names[:3]) + r.stderr)
        r = run("fix", "imp/O_c0.json", "--require", "extrema-at-nodes", "--points", "p1,O/c0/p5,p11,p14", "--out",
                "o.json", cwd=tmp)
        check("fix --points takes the report's point names", r.returncode == 0, r.stderr)
        out = json.load(open(os.path.join(tmp, "o.json"))) if r.returncode == 0 else {}
        check("fix --out keeps point_names", out.get("point_names", [])[:2] == ["O/c0/p0", "O/c0/p1"], str(out)[:200])
        r = run("fix", "imp/O_c0.json", "--points", "zz", cwd=tmp)
        check("fix --points with an unknown name: exit 2", r.returncode == 2 and "'zz'" in r.stderr, r.stderr)
        r = run("import", os.path.join(dejavu, "glyphs", "o.glif"), "--out", "imp2", cwd=tmp)
        doc = json.load(open(os.path.join(tmp, "imp2", "o_c0.json"))) if r.returncode == 0 else {}
        check("a qcurve .glif imports as a quadratic spline", doc.get("degree") == 2, r.stderr)
        check("a lone .glif: one glyph, units per em unknown (no fontinfo.plist beside it)",
              "imported 1 glyph, 2 contours (quadratic, units per em unknown)" in r.stdout, r.stdout)

        # --work: each glyph's budget; a glyph that runs out of it says so in one line naming the flag
        r = run("fix", "Nimbus.ufo", "--glyph", "O", "--require", "extrema-at-nodes,g2-at-smooth-nodes", "--work", "20000",
                "--out", "W.ufo", cwd=tmp)
        check("fix --work 20000: O runs out of work, exit 2, one line naming --work, nothing written",
              r.returncode == 2 and "a larger --work searches further" in r.stderr and r.stderr.count("\n") == 1
              and not os.path.exists(os.path.join(tmp, "W.ufo")), r.stderr)
        # Where the work runs out, the line says so, not the last search's count of evaluations (as few as
        # the work had left: "no certified fix found in 1 evaluations" before)
        r = run("fix", "Nimbus.ufo", "--glyph", "s", "--require", "extrema-at-nodes,g2-at-smooth-nodes", "--work",
                "200000", "--out", "W.ufo", cwd=tmp)
        check("fix --work 200000: s runs out of work, and the line names no count of evaluations",
              r.returncode == 2 and "no certified fix found; where the search stopped" in r.stderr
              and "evaluations" not in r.stderr and "a larger --work searches further" in r.stderr, r.stderr)

        # fix: a copy of the UFO where only moved points' x/y change, on the grid
        r = run("fix", "Nimbus.ufo", "--glyph", "O", "--require", "extrema-at-nodes,g2-at-smooth-nodes", "--out",
                "Fixed.ufo", cwd=tmp)
        check("fix O (extrema and g2 at once) exits 0", r.returncode == 0, r.stderr)
        fixed = os.path.join(tmp, "Fixed.ufo")
        if r.returncode == 0:
            check("the copy has the same files", tree_files(nimbus) == tree_files(fixed))
            same = [f for f in tree_files(nimbus) if f != os.path.join("glyphs", "O_.glif")]
            _, mismatch, errors = filecmp.cmpfiles(nimbus, fixed, same, shallow=False)
            check("every other file is byte-identical", not mismatch and not errors, str(mismatch + errors))
            ok, why = only_xy_changed(os.path.join(nimbus, "glyphs", "O_.glif"), os.path.join(fixed, "glyphs", "O_.glif"))
            check("only x/y of moved points change, to integers", ok, why)
            for gate in ("extrema", "g2"):
                before, after = exact_judge(os.path.join(nimbus, "glyphs", "O_.glif"), gate), exact_judge(
                    os.path.join(fixed, "glyphs", "O_.glif"), gate)
                check("exact judge (%s): the source fails, the fixed glyph passes" % gate,
                      before.returncode == 1 and after.returncode == 0, after.stdout)
            doc = json.loads(r.stdout)
            check("the fix document shows the re-judging of both checks",
                  all([x["after"] for x in c["rejudged"]] == [0, 0] and len(c["rejudged"]) == 2 for c in doc["contours"]),
                  str(doc["contours"]))
            if shutil.which("fontmake"):
                fm = subprocess.run(["fontmake", "-u", fixed, "-o", "otf", "--output-dir", os.path.join(tmp, "otf")],
                                    capture_output=True, text=True, timeout=600)
                check("fontmake builds the fixed source", fm.returncode == 0, fm.stderr[-500:])

        # two gates on a TrueType-flavoured (qcurve) source: DejaVu Sans O
        fixed_glyph(tmp, dejavu, "O", "O_.glif", "curvature-extrema-at-nodes,g2-at-smooth-nodes", "FixedDV.ufo",
                    "extrema,g2", "DejaVu O (qcurve; extrema and g2 at once)")

        # g2 alone on Nimbus g (issue 36's stem example): two stem-to-bowl joins need the bowl's end
        # curvature exactly 0, which the violation-at-a-time rounds construct; the stems stay lines
        g_files = fixed_glyph(tmp, nimbus, "g", "g.glif", "g2-at-smooth-nodes", "FixedG.ufo", "g2",
                              "Nimbus g under g2 (stem-to-bowl joins)")
        if g_files:
            src_g, fix_g = g_files
            # A line's end nodes stay (report/contour_moves.hpp): every on-curve point that begins or
            # ends a `line` segment has the source's coordinates.
            def line_ends(path):
                ends = set()
                for contour in re.findall(r"<contour>(.*?)</contour>", open(path).read(), re.S):
                    pts = re.findall(r"<point ([^>]*)/>", contour)
                    xy = [(re.search(r'\bx="([^"]*)"', p).group(1), re.search(r'\by="([^"]*)"', p).group(1)) for p in pts]
                    for i, p in enumerate(pts):
                        if 'type="line"' in p:
                            ends |= {(i, xy[i]), ((i - 1) % len(pts), xy[(i - 1) % len(pts)])}
                return ends
            check("Nimbus g: every line's end nodes stay where they were", line_ends(src_g) == line_ends(fix_g),
                  str(line_ends(src_g) ^ line_ends(fix_g)))

        # The extrema gate alone on Nimbus S: its fix moves 15 handles, and the snap of all of them at once
        # finds no grid position (the product of their candidates is cut); snapped part by part (parts
        # that share no segment, report/glyph_settle.hpp snap_by_parts) it lands on the grid
        fixed_glyph(tmp, nimbus, "S", "S_.glif", "curvature-extrema-at-nodes", "FixedS.ufo", "extrema",
                    "Nimbus S under curvature-extrema-at-nodes (15 handles move)")

        # Both type gates on Nimbus S: the grid descent from the source finds nothing, the first round
        # leaves 8 of 21 violations, and a descent from there passes (report/glyph_fix.cpp, fix_contour)
        fixed_glyph(tmp, nimbus, "S", "S_.glif", "curvature-extrema-at-nodes,g2-at-smooth-nodes", "FixedS2.ufo",
                    "extrema,g2", "Nimbus S under both type gates (a descent after the first round)")

        # A font's glyphs at once (--glyphs): each failing one fixed on its own and all written back together,
        # each as its single-glyph fix; l passes as it is; n cannot be fixed under both gates (a stem-to-arch
        # join no move passes), so it is listed with its reason and the run exits 1, the others still written
        both = "curvature-extrema-at-nodes,g2-at-smooth-nodes"
        batch = os.path.join(tmp, "Batch.ufo")
        shutil.copytree(nimbus, batch)
        r = run("fix", "Batch.ufo", "--glyphs", "n,o,l,O", "--require", both, "--in-place", cwd=tmp)
        doc = json.loads(r.stdout) if r.stdout.strip() else {}
        entries = {g["glyph"]: g for g in doc.get("glyphs", [])}
        check("fix --glyphs: exit 1 and one stderr line naming the glyph with no fix",
              r.returncode == 1 and len(r.stderr.strip().split("\n")) == 1 and "(n;" in r.stderr, r.stderr)
        check("fix --glyphs: n unfixed with its reason, o and O fixed, l already passing",
              doc.get("summary", {}).get("already") == 1 and doc["summary"]["fixed"] == 2 and
              doc["summary"]["unfixed"] == 1 and not entries["n"]["fixed"] and "n/c0" in entries["n"]["reason"] and
              entries["o"]["fixed"] and entries["O"]["fixed"] and "l" not in entries, str(doc)[:600])
        changed = [f for f in tree_files(nimbus) if open(os.path.join(nimbus, f), "rb").read() !=
                   open(os.path.join(batch, f), "rb").read()]
        check("fix --glyphs --in-place: only o's and O's .glif change", changed == ["glyphs/O_.glif", "glyphs/o.glif"] and
              sorted(doc.get("written", [])) == ["Batch.ufo/glyphs/O_.glif", "Batch.ufo/glyphs/o.glif"],
              str(changed) + str(doc.get("written")))
        for glif in ("o.glif", "O_.glif"):
            ok, why = only_xy_changed(os.path.join(nimbus, "glyphs", glif), os.path.join(batch, "glyphs", glif))
            after = exact_judge(os.path.join(batch, "glyphs", glif), "extrema,g2")
            check("fix --glyphs: %s only x/y to integers, and the exact judge passes it on both gates" % glif,
                  ok and after.returncode == 0, why + after.stdout[:300])
        r = run("fix", "Nimbus.ufo", "--glyph", "o", "--require", both, "--out", "OneO.ufo", cwd=tmp)
        check("fix --glyphs: o's fix is its single-glyph fix, byte for byte", r.returncode == 0 and
              open(os.path.join(tmp, "OneO.ufo", "glyphs", "o.glif")).read() ==
              open(os.path.join(batch, "glyphs", "o.glif")).read(), r.stderr)
        r = run("fix", "Nimbus.ufo", "--glyphs", "o,l", "--require", both, "--out", "BatchOut.ufo", cwd=tmp)
        out_tree = os.path.join(tmp, "BatchOut.ufo")
        same = r.returncode == 0 and tree_files(out_tree) == tree_files(nimbus) and [
            f for f in tree_files(nimbus) if open(os.path.join(nimbus, f), "rb").read() !=
            open(os.path.join(out_tree, f), "rb").read()] == ["glyphs/o.glif"]
        check("fix --glyphs --out: a whole copy in which only o's .glif changes, exit 0", same, r.stderr)
        for args, says in ((["--glyphs", "o", "--glyph", "o", "--out", "Bad1.ufo"], "--glyph and --glyphs"),
                           (["--glyphs", "o", "--points", "p3", "--out", "Bad2.ufo"], "--points: for one glyph"),
                           (["--glyphs", "o", "--out", "BatchOut.ufo"], "BatchOut.ufo: exists"),
                           (["--glyphs", "U+4E00", "--out", "Bad3.ufo"], "names no glyph")):
            r = run("fix", "Nimbus.ufo", *args, "--require", both, cwd=tmp)
            check("fix --glyphs, bad input (%s): exit 2, one line, nothing written" % says,
                  r.returncode == 2 and says in r.stderr and len(r.stderr.strip().split("\n")) == 1 and
                  not any(os.path.exists(os.path.join(tmp, b)) for b in ("Bad1.ufo", "Bad2.ufo", "Bad3.ufo")), r.stderr)
        # --glyphs searches the glyphs the report fails: under g2 alone Nimbus e and r have only info findings
        # (a certified move below half a unit), so the report passes them and the fix leaves them; --strict
        # (as the report's) counts every finding and fixes them too
        r = run("report", "Nimbus.ufo", "--glyphs", "e,r,o", "--require", "g2-at-smooth-nodes", "--out", "rsev",
                "--no-thumbnails", "--quiet", "--fix-budget", "0", cwd=tmp)
        rep = json.load(open(os.path.join(tmp, "rsev", "report.json"))) if r.returncode in (0, 1) else {"splines": []}
        glyph_pass = {}
        for sp in rep["splines"]:
            glyph_pass[sp["glyph"]] = glyph_pass.get(sp["glyph"], True) and sp["status"] == "pass"
        info_only = sorted(g for g, ok in glyph_pass.items() if ok)
        r = run("fix", "Nimbus.ufo", "--glyphs", "e,r,o", "--require", "g2-at-smooth-nodes", "--out", "Sev.ufo", cwd=tmp)
        doc = json.loads(r.stdout) if r.returncode == 0 else {}
        changed = [f for f in tree_files(nimbus) if r.returncode == 0 and open(os.path.join(nimbus, f), "rb").read() !=
                   open(os.path.join(tmp, "Sev.ufo", f), "rb").read()]
        check("fix --glyphs leaves the glyphs the report passes (only info findings): e and r",
              info_only == ["e", "r"] and doc.get("summary", {}).get("below_severity") == info_only and
              changed == ["glyphs/o.glif"], str(info_only) + str(doc.get("summary")) + str(changed) + r.stderr)
        r = run("fix", "Nimbus.ufo", "--glyphs", "e,r,o", "--require", "g2-at-smooth-nodes", "--strict", "--out",
                "SevStrict.ufo", cwd=tmp)
        doc = json.loads(r.stdout) if r.returncode == 0 else {}
        check("fix --glyphs --strict: e and r are fixed too", r.returncode == 0 and
              doc["summary"]["below_severity"] == [] and [(g["glyph"], g["fixed"]) for g in doc["glyphs"]] ==
              [("e", True), ("r", True), ("o", True)], r.stderr + str(doc.get("summary")))
        for args, says in ((["--glyph", "e", "--strict"], "--strict: with --glyphs"),
                           (["--glyphs", "e", "--strict", "--min-severity", "1"], "--strict: not with --min-severity"),
                           (["--glyphs", "e", "--min-severity", "-1"], "--min-severity: -1 is not a distance")):
            r = run("fix", "Nimbus.ufo", *args, "--require", "g2-at-smooth-nodes", "--out", "Bad4.ufo", cwd=tmp)
            check("fix, bad severity option (%s): exit 2, one line, nothing written" % says,
                  r.returncode == 2 and says in r.stderr and not os.path.exists(os.path.join(tmp, "Bad4.ufo")), r.stderr)
        r = run("fix", os.path.join("Nimbus.ufo", "glyphs", "o.glif"), "--glyphs", "o", "--require", both, cwd=tmp)
        check("fix --glyphs on a .glif: exit 2, one line", r.returncode == 2 and "--glyphs selects glyphs of a UFO" in
              r.stderr, r.stderr)

        # --points on a source: the report's names narrow the moves (a named node takes its handles)
        named = ["c0/p8", "c0/p9", "c0/p10", "c1/p2", "c1/p3"]
        r = run("fix", "Nimbus.ufo", "--glyph", "o", "--require", "g2-at-smooth-nodes", "--points", ",".join(named),
                "--out", "FixedP.ufo", cwd=tmp)
        check("fix a source with --points (names as the report prints them) exits 0", r.returncode == 0, r.stderr)
        if r.returncode == 0:
            doc = json.loads(r.stdout)
            whole = ["o/" + n for n in named]
            allowed = set(whole) | {"o/c0/p8", "o/c0/p10", "o/c1/p4"}  # the handles of the named nodes c0/p9, c1/p3
            moved = [m["point"] for c in doc["contours"] for m in c["moves"]]
            check("--points: the document lists the whole names, and only those points (and named nodes' handles) move",
                  doc.get("points") == whole and moved and set(moved) <= allowed, str(doc.get("points")) + str(moved))
            src_o, fix_o = os.path.join(nimbus, "glyphs", "o.glif"), os.path.join(tmp, "FixedP.ufo", "glyphs", "o.glif")
            before, after = exact_judge(src_o, "g2"), exact_judge(fix_o, "g2")
            check("--points: exact judge (g2): o fails, the fix moving only the named points passes",
                  before.returncode == 1 and after.returncode == 0, after.stdout)
        for bad, says in (("zz", "'zz' names no point"), ("p9", "give the whole name"),
                          ("g/c0/p0", "names no point")):
            r = run("fix", "Nimbus.ufo", "--glyph", "o", "--require", "g2-at-smooth-nodes", "--points", bad,
                    "--out", "Bad.ufo", cwd=tmp)
            check("--points %s on a source: exit 2, one line, nothing written" % bad,
                  r.returncode == 2 and says in r.stderr and r.stderr.count("\n") == 1
                  and not os.path.exists(os.path.join(tmp, "Bad.ufo")), r.stderr)
        # a <point>'s name attribute names it too; a failing contour with no named point is not fixed
        labelled = os.path.join(tmp, "PointNames.ufo")
        shutil.copytree(nimbus, labelled)
        glif = os.path.join(labelled, "glyphs", "o.glif")
        text = open(glif).read()
        for xy, label in (('x="510" y="82"', "r1"), ('x="510" y="254" type="curve"', "right"), ('x="510" y="436"', "r2")):
            text = text.replace('<point ' + xy, '<point ' + xy + ' name="%s"' % label, 1)
        open(glif, "w").write(text)
        r = run("fix", "PointNames.ufo", "--glyph", "o", "--require", "g2-at-smooth-nodes", "--points", "r1,right,r2",
                "--out", "PointNamesFixed.ufo", cwd=tmp)
        doc = json.loads(r.stdout) if r.returncode == 0 else {"contours": []}
        c0 = [c for c in doc["contours"] if c["contour"] == 0]
        c1 = [c for c in doc["contours"] if c["contour"] == 1]
        check("--points takes a <point>'s name attribute: o/c0 is fixed with the named points",
              r.returncode == 0 and c0 and c0[0]["fixed"] and c0[0]["moves"] and
              all(m["point"] in ("o/c0/p8", "o/c0/p9", "o/c0/p10") for m in c0[0]["moves"]) and
              {m.get("label") for m in c0[0]["moves"]} <= {"r1", "right", "r2"}, r.stderr + str(c0))
        check("--points: o/c1, with none of the named points, is left as it is (untouched, still failing, not moved)",
              c1 and c1[0].get("untouched") and not c1[0]["moves"] and
              all(x["after"] == x["before"] > 0 for x in c1[0]["rejudged"]), str(c1))
        r = run("fix", "Nimbus.ufo", "--glyph", "g", "--require", "g2-at-smooth-nodes", "--points", "g/c0/p0", cwd=tmp)
        check("--points naming a line's end node: exit 2, one line (a line stays a line)",
              r.returncode == 2 and "g/c0/p0 ends a straight line" in r.stderr and r.stderr.count("\n") == 1, r.stderr)

        # what no move can do: g2 where a line meets a quadratic curve (DejaVu e), said at once
        r = run("fix", "DejaVu.ufo", "--glyph", "e", "--require", "curvature-extrema-at-nodes,g2-at-smooth-nodes",
                "--out", "FixedE.ufo", cwd=tmp)
        check("fix DejaVu e: a smooth line-to-quadratic join under g2 is named as unfixable (exit 2, one line)",
              r.returncode == 2 and "joins a line to a quadratic curve" in r.stderr and r.stderr.count("\n") == 1
              and not os.path.exists(os.path.join(tmp, "FixedE.ufo")), r.stderr)
        # an added on-curve point cannot help a quadratic (its pieces are flat only where straight): not advised
        check("fix DejaVu e: the advice is to accept the jump or draw in cubics, not to add an on-curve point",
              "nor would an added on-curve point" in r.stderr and "draw the curve in cubics" in r.stderr
              and "(add an on-curve point" not in r.stderr, r.stderr)

        # several gates on a plain spline file (cmr import's), on the grid
        r = run("import", "Nimbus.ufo", "--glyphs", "O", "--out", "impm", cwd=tmp)
        r = run("fix", "impm/O_c1.json", "--require", "curvature-extrema-at-nodes,g2-at-smooth-nodes", "--out", "m.json",
                cwd=tmp)
        check("fix FILE.json --require A,B exits 0", r.returncode == 0, r.stderr)
        if r.returncode == 0:
            doc, fixed_doc = json.loads(r.stdout), json.load(open(os.path.join(tmp, "m.json")))
            check("FILE.json --require A,B: both checks re-judged to 0",
                  [x["after"] for x in doc["contours"][0]["rejudged"]] == [0, 0], r.stdout[:300])
            pts = [p for p in fixed_doc["points"]]
            check("FILE.json --require A,B: integer coordinates, names kept",
                  all(float(v).is_integer() for p in pts for v in p) and fixed_doc.get("point_names", [""])[0] == "O/c1/p0",
                  str(pts[:3]))
            rj = run("report", "m.json", "--require", "curvature-extrema-at-nodes,g2-at-smooth-nodes", "--no-fixes",
                     "--no-thumbnails", "--quiet", "--out", "mrep", cwd=tmp)
            check("FILE.json --require A,B: cmr report passes the fixed file", rj.returncode == 0, rj.stdout + rj.stderr)
        # --points there too: the file's names narrow the moves (the named nodes p3, p9 take their handles)
        r = run("fix", "impm/O_c1.json", "--require", "curvature-extrema-at-nodes,g2-at-smooth-nodes", "--points",
                "p1,p3,p5,p7,p9,p11", "--out", "mp.json", cwd=tmp)
        check("FILE.json --require A,B --points exits 0", r.returncode == 0, r.stderr)
        if r.returncode == 0:
            doc = json.loads(r.stdout)
            named = {"O/c1/p%d" % k for k in (1, 3, 5, 7, 9, 11)}
            moved = {m["point"] for m in doc["contours"][0]["moves"]}
            check("FILE.json --points: only the named points and the named nodes' handles move",
                  moved and moved <= named | {"O/c1/p2", "O/c1/p4", "O/c1/p8", "O/c1/p10"} and
                  set(doc.get("points", [])) == named, str(sorted(moved)))
            rj = run("report", "mp.json", "--require", "curvature-extrema-at-nodes,g2-at-smooth-nodes", "--no-fixes",
                     "--no-thumbnails", "--quiet", "--out", "mprep", cwd=tmp)
            check("FILE.json --points: cmr report passes the fixed file", rj.returncode == 0, rj.stdout + rj.stderr)
        r = run("fix", "impm/O_c1.json", "--require", "curvature-extrema-at-nodes,g2-at-smooth-nodes", "--points", "99",
                cwd=tmp)
        check("FILE.json --require A,B --points 99: exit 2, one line",
              r.returncode == 2 and "99 is outside" in r.stderr and r.stderr.count("\n") == 1, r.stderr)
        open(os.path.join(tmp, "open.json"), "w").write(json.dumps(
            {"degree": 3, "points": [[0, 0], [1, 2], [3, 3], [4, 0], [6, 1], [7, 3], [9, 0]],
             "knots": [0, 0, 0, 0, 1, 1, 1, 2, 2, 2, 2]}))
        r = run("fix", "open.json", "--require", "curvature-extrema-at-nodes,g2-at-smooth-nodes", "--out", "oo.json",
                cwd=tmp)
        check("FILE.json --require A,B on an open spline: exit 2, one line, nothing written",
              r.returncode == 2 and r.stderr.count("\n") == 1 and not os.path.exists(os.path.join(tmp, "oo.json")),
              r.stderr)

        # the report's own fix search: one fix for every required check, re-judged check by check.
        # Its search has 2 s a contour (kReportFixSeconds), which a sanitizer
        # build (about 10 times slower) spends before it finds O's fix.
        if os.environ.get("CMR_SANITIZER_BUILD") == "1":
            print("SKIP report's own all-checks fix: 2 s a contour is too short in a sanitizer build")
        else:
            r = run("report", "Nimbus.ufo", "--glyphs", "O", "--require", "curvature-extrema-at-nodes,g2-at-smooth-nodes",
                    "--out", "rall", "--quiet", *SLOW_BUILD_BUDGET, cwd=tmp)
            doc = json.load(open(os.path.join(tmp, "rall", "report.json"))) if r.returncode in (0, 1) else {"splines": []}
            alls = [(s["name"], f) for s in doc["splines"] for f in s.get("certified_fixes", []) if f["check"].startswith("all:")]
            check("report: each failing contour gets one fix of all required checks",
                  len(alls) == 2 and all(f["found"] for _, f in alls), str(alls)[:300])
            check("report: that fix is re-judged against every check, each to 0",
                  all([x["check"] for x in f["rejudged"]] == ["curvature-extrema-at-nodes", "g2-at-smooth-nodes:0.05"]
                      and all(x["before"] > 0 or x["check"].startswith("g2") for x in f["rejudged"])
                      and all(x["after"] == 0 for x in f["rejudged"]) for _, f in alls), str(alls)[:300])
            page = open(os.path.join(tmp, "rall", "font.html")).read() if os.path.exists(os.path.join(tmp, "rall", "font.html")) else ""
            check("report: the page shows the re-judging", "re-judged: curvature-extrema-at-nodes" in page)
            r = run("import", "Nimbus.ufo", "--glyphs", "O", "--out", "impr", cwd=tmp)
            for name, f in alls:
                path = os.path.join(tmp, "impr", "O_" + name.split("/")[1] + ".json")
                sp = json.load(open(path))
                for m in f["moves"]:
                    sp["points"][m["point"]] = m["to"]
                json.dump(sp, open(os.path.join(tmp, "rall_" + name.split("/")[1] + ".json"), "w"))
                rj = run("report", "rall_" + name.split("/")[1] + ".json", "--require",
                         "curvature-extrema-at-nodes,g2-at-smooth-nodes", "--no-thumbnails", "--quiet", "--out",
                         "rallj_" + name.split("/")[1], cwd=tmp)
                check("report's all-checks fix of %s: integer moves that pass both gates when applied" % name,
                      rj.returncode == 0 and all(float(v).is_integer() for m in f["moves"] for v in m["to"]),
                      rj.stdout + rj.stderr)

        # --in-place: the .glif rewritten, no other file touched
        inplace = os.path.join(tmp, "InPlace.ufo")
        shutil.copytree(nimbus, inplace)
        r = run("fix", "InPlace.ufo", "--glyph", "o", "--require", "g2-at-smooth-nodes", "--in-place", cwd=tmp)
        check("fix --in-place exits 0", r.returncode == 0, r.stderr)
        changed = [f for f in tree_files(nimbus) if not filecmp.cmp(os.path.join(nimbus, f), os.path.join(inplace, f), False)]
        check("--in-place changes only o.glif", changed == [os.path.join("glyphs", "o.glif")], str(changed))
        if changed:
            ok, why = only_xy_changed(os.path.join(nimbus, "glyphs", "o.glif"), os.path.join(inplace, "glyphs", "o.glif"))
            check("--in-place changes only x/y", ok, why)

        # a <point>'s name attribute is shown beside the point's name
        labelled = os.path.join(tmp, "Labelled.ufo")
        shutil.copytree(nimbus, labelled)
        lg = os.path.join(labelled, "glyphs", "O_.glif")
        open(lg, "w").write(open(os.path.join(nimbus, "glyphs", "O_.glif")).read().replace(
            '<point x="180" y="741"/>', '<point x="180" y="741" name="topleft"/>', 1))
        r = run("import", "Labelled.ufo", "--glyphs", "O", "--out", "lab", cwd=tmp)
        doc = json.load(open(os.path.join(tmp, "lab", "O_c0.json"))) if r.returncode == 0 else {}
        check("import: point_labels carries the <point name>", doc.get("point_labels", [None, None])[1] == "topleft"
              and doc.get("point_names", [None, None])[1] == "O/c0/p1", str(doc.get("point_labels")))
        r = run("fix", "Labelled.ufo", "--glyph", "O", "--require", "curvature-extrema-at-nodes", "--out", "LabFixed.ufo",
                cwd=tmp)
        moved = [m for c in json.loads(r.stdout)["contours"] for m in c["moves"]] if r.returncode == 0 else []
        check("fix: a moved point's label beside its name",
              any(m["point"] == "O/c0/p1" and m.get("label") == "topleft" for m in moved), str(moved)[:300])

        # bad input: one line naming the file and the line, exit 2, nothing written
        bad = os.path.join(tmp, "Bad.ufo")
        shutil.copytree(nimbus, bad)
        glif = os.path.join(bad, "glyphs", "O_.glif")
        text = open(glif).read()
        open(glif, "w").write(text.replace('<point x="180" y="741"/>', '<point x="180" y="nan"/>', 1))
        r = run("import", "Bad.ufo", "--glyphs", "O", "--out", "bad", cwd=tmp)
        check("a non-finite coordinate: exit 2, file and line", r.returncode == 2 and re.search(r"O_\.glif:\d+:", r.stderr)
              and r.stderr.count("\n") == 1 and not os.path.exists(os.path.join(tmp, "bad")), r.stderr)
        open(glif, "w").write(text.replace("</contour>", "<contour>", 1))
        r = run("import", "Bad.ufo", "--glyphs", "O", "--out", "bad", cwd=tmp)
        check("malformed .glif XML: exit 2, file and line", r.returncode == 2 and re.search(r"O_\.glif:\d+: not well-formed",
              r.stderr), r.stderr)
        r = run("report", "Bad.ufo", "--out", "rb", "--no-thumbnails", "--quiet", cwd=tmp)
        check("in a report a broken glyph is invalid, the others judged", r.returncode == 2 and "1 invalid" in r.stdout,
              r.stdout + r.stderr)
        open(glif, "w").write(text.replace('<point x="38" y="587"/>', "", 1))
        r = run("import", "Bad.ufo", "--glyphs", "O", "--out", "bad", cwd=tmp)
        check("a curve point after 1 off-curve point is refused", r.returncode == 2 and "after 1 off-curve" in r.stderr,
              r.stderr)
        open(glif, "w").write(text.replace('type="curve" smooth="yes"/>', 'type="qcurve"/>', 1))
        r = run("import", "Bad.ufo", "--glyphs", "O", "--out", "bad", cwd=tmp)
        check("a contour mixing curve and qcurve is refused", r.returncode == 2 and "mixes curve and qcurve" in r.stderr,
              r.stderr)
        open(glif, "w").write(text.replace("<outline>", '<outline>\n    <component base="o"/>\n    '
                                           '<contour><point x="1" y="2" type="move"/><point x="5" y="2" type="line"/></contour>', 1))
        r = run("import", "Bad.ufo", "--glyphs", "O", "--out", "comp", cwd=tmp)
        check("components and open contours: notes, the rest imported",
              r.returncode == 0 and "1 component not judged" in r.stderr and "is open" in r.stderr, r.stderr)
        os.remove(glif)
        r = run("import", "Bad.ufo", "--glyphs", "O", "--out", "bad", cwd=tmp)
        check("a glyph file listed but missing: exit 2", r.returncode == 2 and "missing (listed in contents.plist" in r.stderr,
              r.stderr)
        info = os.path.join(bad, "fontinfo.plist")
        info_text = open(info).read() if os.path.exists(info) else None
        for upm in ("1" + "0" * 78, "0", "-1000"):
            open(info, "w").write('<?xml version="1.0" encoding="UTF-8"?>\n<plist version="1.0">\n<dict>\n'
                                  '<key>unitsPerEm</key>\n<real>%s</real>\n</dict>\n</plist>\n' % upm)
            r = run("import", "Bad.ufo", "--out", "bad", cwd=tmp)
            check("unitsPerEm %s: exit 2 naming the line" % upm[:8], r.returncode == 2 and re.search(
                r"fontinfo\.plist:5: unitsPerEm must be from 1 to 16384", r.stderr), r.stderr)
        if info_text is None:
            os.remove(info)
        else:
            open(info, "w").write(info_text)
        lc = os.path.join(bad, "layercontents.plist")
        layers = open(lc).read()
        open(lc, "w").write(re.sub(r"</array>\s*</array>", "</array>\n<array><string>public.default</string>"
                                   "<string>glyphs.x</string></array>\n</array>", layers))
        r = run("report", "Bad.ufo", "--out", "rb2", "--no-thumbnails", "--quiet", cwd=tmp)
        check("two layers with one name: exit 2 naming the line", r.returncode == 2 and re.search(
            r"layercontents\.plist:\d+: two layers", r.stdout + r.stderr), r.stdout + r.stderr)
        open(os.path.join(bad, "metainfo.plist"), "w").write("<plist><dict><key>formatVersion</key>")
        r = run("import", "Bad.ufo", "--out", "bad", cwd=tmp)
        check("a malformed plist: exit 2 naming the line", r.returncode == 2 and "metainfo.plist:" in r.stderr, r.stderr)
        r = run("fix", "Nimbus.ufo", "--glyph", "nosuch", "--require", "extrema-at-nodes", "--out", "x.ufo", cwd=tmp)
        check("fix of an unknown glyph: exit 2", r.returncode == 2 and "no glyph named 'nosuch'" in r.stderr, r.stderr)

        # a variable font's instance (--location, FreeType's variation API);
        # Inter comes from Debian's fonts-inter-variable (tools/setup.sh)
        inter = "/usr/share/fonts/truetype/inter-vf/Inter-roman.var.ttf"
        check("Inter's variable font is installed (tools/setup.sh: fonts-inter-variable)", os.path.exists(inter), inter)
        if os.path.exists(inter):
            pts = {}
            for w in ("100", "900"):
                r = run("import", inter, "--glyphs", "O", "--location", "wght=" + w, "--out", "v" + w, cwd=tmp)
                files = sorted(f for f in os.listdir(os.path.join(tmp, "v" + w)) if f.endswith(".json")) if r.returncode == 0 else []
                pts[w] = json.load(open(os.path.join(tmp, "v" + w, files[0])))["points"] if files else None
            check("--location: two instances of Inter differ", pts["100"] and pts["900"] and pts["100"] != pts["900"]
                  and len(pts["100"]) == len(pts["900"]), str(pts)[:200])
            r = run("import", inter, "--glyphs", "O", "--location", "wght=2000", "--out", "vbad", cwd=tmp)
            check("--location outside the axis: exit 2", r.returncode == 2 and "outside the axis's range" in r.stderr, r.stderr)
            r = run("import", inter, "--glyphs", "O", "--location", "zzzz=1", "--out", "vbad", cwd=tmp)
            check("--location on an unknown axis: exit 2", r.returncode == 2 and "no axis 'zzzz'" in r.stderr, r.stderr)
            # the report says which instance it judged, and shards of two instances are not one run
            for w in ("100", "900"):
                r = run("report", inter, "--glyphs", "O,S", "--location", "wght=" + w, "--require",
                        "curvature-extrema-at-nodes", "--no-thumbnails", "--quiet", "--shard", "1/1", "--out", "r" + w,
                        cwd=tmp)
                at = json.load(open(os.path.join(tmp, "r" + w, "report.json")))["settings"].get("location") \
                    if r.returncode in (0, 1) else None
                check("report --location wght=" + w + ": settings.location is the instance", at == {"wght": int(w)},
                      r.stderr + str(at))
            r = run("report", "--merge", "r100", "r900", "--out", "rm", cwd=tmp)
            check("merge of two instances' shards: refused", r.returncode == 2 and "settings" in r.stderr, r.stderr)
        r = run("import", DEJAVU, "--glyphs", "O", "--location", "wght=400", "--out", "vbad", cwd=tmp)
        check("--location on a font without fvar: exit 2", r.returncode == 2 and "not a variable font" in r.stderr, r.stderr)

        # a designspace: its masters reported as fonts
        ds = os.path.join(tmp, "Family.designspace")
        open(ds, "w").write('<?xml version="1.0"?>\n<designspace format="4.1">\n<axes>\n'
                            '<axis tag="wght" name="Weight" minimum="400" maximum="700" default="400"/>\n</axes>\n'
                            '<sources>\n<source filename="Nimbus.ufo"><location><dimension name="Weight" xvalue="400"/>'
                            '</location></source>\n<source filename="InPlace.ufo"><location><dimension name="Weight" '
                            'xvalue="700"/></location></source>\n</sources>\n</designspace>\n')
        r = run("report", "Family.designspace", "--out", "rd", "--no-thumbnails", "--quiet", cwd=tmp)
        check("a designspace reports its masters", "2 fonts" in r.stdout, r.stdout + r.stderr)
        doc = open(ds).read()
        open(ds, "w").write(doc.replace("InPlace.ufo", "Missing.ufo"))
        r = run("report", "Family.designspace", "--out", "rd2", "--no-thumbnails", "--quiet", cwd=tmp)
        check("a designspace naming a missing source: exit 2 with the line",
              r.returncode == 2 and re.search(r"Family\.designspace:\d+: the source 'Missing.ufo' does not exist", r.stderr),
              r.stderr)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    passed = sum(results)
    print("%d passed, %d failed" % (passed, len(results) - passed))
    sys.exit(0 if passed == len(results) else 1)


main()
