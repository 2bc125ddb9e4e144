#!/usr/bin/python3
"""The resume cache of `cmr report` (report/report_cache.hpp, issue 37):
a rerun into the same --out takes unchanged glyphs from OUT/report.cache,
judges the others, and writes the report a fresh run writes, byte for byte.

    report_cache_test.py CMR

A two-master designspace of 20 glyphs (the kink of
tools/make_test_designspace.py, scaled by 1..20; every other one with
proportional handles), judged by g1-between-masters and
curvature-between-masters with thumbnails (--no-fixes: a certified fix's
report carries its search time, which no two runs share):
  - the second run judges 0 glyphs and its report.json and font page equal
    the first's and a fresh --no-cache run's;
  - one .glif edited in one master: 1 glyph judged, 19 taken, the report
    equal to a fresh run on the edited sources (whose finding differs);
  - other options: every glyph judged;
  - a cache flipped in one byte, cut short, foreign, from another build, or
    a symbolic link: ignored with one note, the report still the fresh one;
  - --no-cache writes none (and the old one goes);
  - a UFO without interpolation gates, and a CFF2 variable font (when
    fontmake is installed), reuse their glyphs too.
Prints "N passed, M failed" and exits 1 on any failure.
"""
import hashlib
import os
import re
import shutil
import subprocess
import sys
import tempfile

import ufoLib2
from fontTools.designspaceLib import AxisDescriptor, DesignSpaceDocument, SourceDescriptor

CMR = sys.argv[1]
results = []


def check(name, ok, detail=""):
    results.append(bool(ok))
    print(("PASS " if ok else "FAIL ") + name + ("" if ok else ": " + str(detail)[:2000]))


# A sanitizer build (about 10 times slower) would spend the default 20 s fix
# budget, and a run whose budget ran out is not byte-identical to a rerun.
SLOW_BUILD_BUDGET = ["--fix-budget", "400"] if os.environ.get("CMR_SANITIZER_BUILD") == "1" else []


def run(*args):
    return subprocess.run([CMR, "report", *args, *SLOW_BUILD_BUDGET], capture_output=True, text=True, timeout=900)


def read(path):
    with open(path, "rb") as f:
        return f.read()


def counts(proc):
    """(taken, judged) from the cache's note, None when there is none."""
    m = re.search(r"report\.cache: (\d+) glyphs? unchanged, taken from it; (\d+) judged", proc.stderr)
    return (int(m.group(1)), int(m.group(2))) if m else None


def notes(proc):
    return [l for l in proc.stderr.splitlines() if l.startswith("cmr: note:")]


# Node p0 at (0, 0) with incoming tangent u and outgoing v, times F (an integer: G1 stays exact).
REGULAR = {"u": (100, 0), "v": (200, 0), "b": (0, 400), "h": (300, 400), "k": (-300, 400)}
BOLD_KINK = {"u": (60, 30), "v": (240, 120), "b": (0, 420), "h": (330, 420), "k": (-330, 420)}
BOLD_PROPORTIONAL = dict(BOLD_KINK, v=(120, 60))
NAMES = [chr(ord("A") + i) for i in range(20)]


def add_glyph(font, name, m, f):
    g = font.newGlyph(name)
    g.unicodes = [ord(name)]
    g.width = 600 * f
    pen = g.getPointPen()
    sc = lambda p: (p[0] * f, p[1] * f)
    pen.beginPath()
    pen.addPoint((0, 0), segmentType="curve", smooth=True)
    pen.addPoint(sc(m["v"]))
    pen.addPoint(sc(m["h"]))
    pen.addPoint(sc(m["b"]), segmentType="curve")
    pen.addPoint(sc(m["k"]))
    pen.addPoint(sc((-m["u"][0], -m["u"][1])))
    pen.endPath()


def family(out):
    for style, bold in (("Regular", False), ("Bold", True)):
        font = ufoLib2.Font()
        font.info.familyName = "Cache Test"
        font.info.styleName = style
        font.info.unitsPerEm = 1000
        for i, name in enumerate(NAMES):
            m = (BOLD_KINK if i % 2 == 0 else BOLD_PROPORTIONAL) if bold else REGULAR
            add_glyph(font, name, m, i + 1)
        font.save(os.path.join(out, style + ".ufo"), overwrite=True)
    doc = DesignSpaceDocument()
    a = AxisDescriptor()
    a.name, a.tag, a.minimum, a.default, a.maximum = "Weight", "wght", 400, 400, 700
    doc.addAxis(a)
    for style, w in (("Regular", 400), ("Bold", 700)):
        s = SourceDescriptor()
        s.filename, s.name, s.styleName, s.familyName = style + ".ufo", style, style, "Cache Test"
        s.location = {"Weight": w}
        doc.addSource(s)
    path = os.path.join(out, "Family.designspace")
    doc.write(path)
    return path


def same_report(a, b):
    return read(os.path.join(a, "report.json")) == read(os.path.join(b, "report.json")) and \
        read(os.path.join(a, "font.html")) == read(os.path.join(b, "font.html"))


with tempfile.TemporaryDirectory() as tmp:
    ds = family(tmp)
    gates = ["--require", "g1-between-masters,curvature-between-masters", "--glyphs", "all", "--jobs", "2", "--no-fixes"]
    qa = os.path.join(tmp, "qa")
    cache = os.path.join(qa, "report.cache")

    def fresh(name, *extra):
        out = os.path.join(tmp, name)
        p = run(ds, *gates, *extra, "--no-cache", "--out", out)
        check(name + ": a fresh run exits 1 (kinks)", p.returncode == 1, p.stderr)
        check(name + ": --no-cache writes no cache", not os.path.exists(os.path.join(out, "report.cache")))
        return out

    p1 = run(ds, *gates, "--out", qa)
    check("first run exits 1 (10 kinks)", p1.returncode == 1, p1.stdout + p1.stderr)
    check("first run: no cache to read, no note", counts(p1) is None and not notes(p1), p1.stderr)
    check("first run writes report.cache", os.path.isfile(cache))
    # The file's form (report/report_cache.hpp): the header names the build by the SHA-256 of the cmr executable,
    # and each record's checksum is the SHA-256 of its payload (hashlib's, independently).
    data = read(cache)
    head, _, rest = data.partition(b"\n")
    build, _, rest = rest.partition(b"\n")
    records = []
    while len(rest) >= 72:
        n = int.from_bytes(rest[32:40], "little")
        records.append(hashlib.sha256(rest[72:72 + n]).digest() == rest[40:72] and len(rest) >= 72 + n)
        rest = rest[72 + n:]
    check("report.cache: its header, the build's SHA-256, 20 records each with its payload's SHA-256",
          head == b"cmr report cache 1" and build.decode() == hashlib.sha256(read(CMR)).hexdigest() and
          records == [True] * 20 and rest == b"", (head, build, records))
    first = os.path.join(tmp, "first")
    shutil.copytree(qa, first)
    ref = fresh("fresh")
    check("a fresh run's report equals the first run's", same_report(first, ref))

    p2 = run(ds, *gates, "--out", qa)
    check("rerun: 20 glyphs taken from the cache, 0 judged", counts(p2) == (20, 0), p2.stderr)
    check("rerun: report.json and font.html byte-identical to a fresh run", same_report(qa, ref))
    check("rerun: same exit code and summary counts", p2.returncode == p1.returncode and
          p2.stdout.split(";")[:2] == p1.stdout.split(";")[:2], p1.stdout + p2.stdout)

    # With the certified fixes (the default): the same but for the fixes' search times.
    def masked(folder):
        j = re.sub(rb'"seconds":[-+0-9.e]+', b'"seconds":T', read(os.path.join(folder, "report.json")))
        h = re.sub(rb'[0-9.]+ s; ', b'T s; ', read(os.path.join(folder, "font.html")))
        return j, h
    fixes = [a for a in gates if a != "--no-fixes"]
    fx = os.path.join(tmp, "fixes")
    q1 = run(ds, *fixes, "--out", fx)
    q2 = run(ds, *fixes, "--out", fx)
    q3 = run(ds, *fixes, "--no-cache", "--out", os.path.join(tmp, "fixes_fresh"))
    check("with fixes: the rerun takes every glyph, its report a fresh run's but for search times",
          q1.returncode == q2.returncode == q3.returncode == 1 and counts(q2) == (20, 0) and
          masked(fx) == masked(os.path.join(tmp, "fixes_fresh")), q2.stderr)

    # One .glif in one master: glyph C's Bold handles made proportional (its kink goes).
    glif = os.path.join(tmp, "Bold.ufo", "glyphs", "C_.glif")
    text = open(glif).read()
    edited = text.replace('x="720" y="360"', 'x="360" y="180"')
    check("the edit changes C's Bold .glif", edited != text)
    open(glif, "w").write(edited)
    p3 = run(ds, *gates, "--out", qa)
    check("after one .glif edit: 19 glyphs taken, 1 judged", counts(p3) == (19, 1), p3.stderr)
    ref2 = fresh("fresh2")
    check("after the edit: the report equals a fresh run's", same_report(qa, ref2))
    check("after the edit: the report is not the old one (C's kink is gone)",
          read(os.path.join(qa, "report.json")) != read(os.path.join(first, "report.json")) and
          p3.returncode == 1 and "9 findings" in p3.stdout and "10 findings" in p1.stdout, p1.stdout + p3.stdout)

    p4 = run(ds, "--require", "g1-between-masters", "--glyphs", "all", "--out", qa)
    check("other gates: every glyph judged", counts(p4) == (0, 20), p4.stderr)
    p5 = run(ds, *gates, "--out", qa)
    check("back to the first gates: every glyph judged (the cache holds the last run's)", counts(p5) == (0, 20), p5.stderr)
    p6 = run(ds, *gates, "--out", qa)
    check("and again: every glyph taken", counts(p6) == (20, 0) and same_report(qa, ref2), p6.stderr)

    # Damaged caches: each ignored with one note, the report the fresh one, a good cache written again.
    def damaged(name, damage, expect, taken=None):
        damage(cache)
        p = run(ds, *gates, "--out", qa)
        ns = [n for n in notes(p) if "report.cache:" in n and "taken from it" not in n]
        check(name + ": one note", len(ns) == 1 and expect in ns[0], p.stderr)
        check(name + ": glyphs taken, judged " + str(taken), counts(p) == taken, p.stderr)
        check(name + ": the report equals a fresh run's", same_report(qa, ref2))
        p = run(ds, *gates, "--out", qa)
        check(name + ": the next run takes every glyph again", counts(p) == (20, 0) and not
              [n for n in notes(p) if "taken from it" not in n], p.stderr)

    def flip_last(path):
        data = bytearray(read(path))
        data[-10] ^= 0x55
        open(path, "wb").write(bytes(data))

    def cut(path):
        data = read(path)
        open(path, "wb").write(data[:len(data) - 100])

    def foreign(path):
        os.remove(path)
        open(path, "w").write('{"not": "a cache"}\n')

    def other_build(path):
        data = read(path)
        head, _, rest = data.partition(b"\n")
        build, _, rest = rest.partition(b"\n")
        open(path, "wb").write(head + b"\n" + b"0" * len(build) + b"\n" + rest)

    def link(path):
        os.rename(path, path + ".real")
        os.symlink(os.path.basename(path) + ".real", path)

    damaged("one byte flipped", flip_last, "did not match its checksum", (19, 1))
    damaged("cut short", cut, "ignored, every glyph judged again: cut short")
    damaged("a foreign file", foreign, "not a cmr report cache")
    damaged("another build", other_build, "written by another build of cmr")
    # A symbolic link is never read; the run writes its outputs through it (as it does any output path that is
    # a link to a file: docs/outputs.md), so it stays a link, and is ignored again.
    link(cache)
    for k in range(2):
        p = run(ds, *gates, "--out", qa)
        check("a symbolic link, run %d: one note, every glyph judged, the fresh report" % (k + 1),
              counts(p) is None and len([n for n in notes(p) if "a symbolic link" in n]) == 1 and
              same_report(qa, ref2), p.stderr)
    check("the link stays a link, the new cache written through it", os.path.islink(cache) and
          read(cache + ".real").startswith(b"cmr report cache 1\n"))
    os.remove(cache)
    os.rename(cache + ".real", cache)
    p = run(ds, *gates, "--out", qa)
    check("the cache the link pointed to, put in place, is taken", counts(p) == (20, 0), p.stderr)

    p = run(ds, *gates, "--no-cache", "--out", qa)
    check("--no-cache: nothing taken, the old cache removed", counts(p) is None and not os.path.exists(cache), p.stderr)

    # A UFO without interpolation gates (severity on by default).
    ufo_qa = os.path.join(tmp, "ufo_qa")
    # No fix budget: a glyph whose fix search the budget cut is judged again
    # (the cache keeps whole results only), and on a loaded machine the
    # on-grid fixes of 20 glyphs can take longer than the default 20 s.
    u = [os.path.join(tmp, "Regular.ufo"), "--require", "curvature-extrema-at-nodes", "--glyphs", "all",
         "--fix-budget", "0", "--out", ufo_qa]
    q1 = run(*u)
    keep = read(os.path.join(ufo_qa, "report.json"))
    q2 = run(*u)
    check("UFO: the rerun takes its 20 glyphs", q1.returncode in (0, 1) and counts(q2) == (20, 0), q1.stderr + q2.stderr)
    check("UFO: its report.json is byte-identical", q1.returncode == q2.returncode and
          read(os.path.join(ufo_qa, "report.json")) == keep)

    # A CFF2 variable font built from the designspace (fontmake, when installed).
    fontmake = shutil.which("fontmake")
    if fontmake:
        vf = os.path.join(tmp, "vf", "Family-VF.otf")
        b = subprocess.run([fontmake, "-m", ds, "-o", "variable-cff2", "--output-dir", os.path.join(tmp, "vf")],
                           capture_output=True, text=True, timeout=300)
        if b.returncode == 0:
            vf_qa = os.path.join(tmp, "vf_qa")
            v = [vf, "--require", "g1-between-masters", "--glyphs", "all", "--out", vf_qa]
            v1 = run(*v)
            keep = read(os.path.join(vf_qa, "report.json"))
            v2 = run(*v)
            check("variable font: the rerun takes every glyph", v1.returncode in (0, 1) and counts(v2) is not None and
                  counts(v2)[1] == 0 and counts(v2)[0] > 0, v1.stderr + v2.stderr)
            check("variable font: report.json byte-identical", read(os.path.join(vf_qa, "report.json")) == keep)
        else:
            print("SKIP variable font: fontmake failed: " + b.stderr[-300:])
    else:
        print("SKIP variable font: no fontmake")

passed = sum(results)
print(f"{passed} passed, {len(results) - passed} failed")
sys.exit(0 if passed == len(results) else 1)
