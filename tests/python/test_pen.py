"""cmr.pen.SplinePen over fontTools glyphs gives the splines of `cmr import`
(points, knots, point names) and, through cmr.analyze, the verdicts of
`cmr import` + `cmr analyze`: DejaVu Sans (TrueType) and Nimbus Sans (CFF)."""

import json
import os

import pytest

import cmr
import cmr.fonttools
from cmr.pen import SplinePen
from conftest import cli_json, run_cmr

ttLib = pytest.importorskip("fontTools.ttLib")

DEJAVU = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"
NIMBUS = "/usr/share/fonts/opentype/urw-base35/NimbusSans-Regular.otf"


def imported(tmp_path, font, chars):
    """cmr import's spline files of the glyphs of `chars`, by contour name."""
    out = tmp_path / "import"
    run_cmr("import", font, "--glyphs", ",".join(chars), "--out", out)
    files = {}
    for path in sorted(out.glob("*.json")):
        doc = json.loads(path.read_text())
        files[doc["name"]] = (path, doc)
    return files


def pen_splines(font, names):
    glyphs = ttLib.TTFont(font).getGlyphSet()
    out = {}
    for name in names:
        for d in cmr.fonttools.glyph_splines(glyphs, name):
            out[d["name"]] = d
    return out


@pytest.mark.parametrize("font,chars", [
    (DEJAVU, ["O"]),
    (DEJAVU, ["a", "S", "g", "e", "R"]),
    (NIMBUS, ["O", "a", "S", "g", "R", "N"]),
    (DEJAVU, ["\u00c1", "\u00e7", "\u00f6"]),  # composites: base glyph and accent through addComponent
    (NIMBUS, ["\u00c1", "\u00e7", "\u00f6"]),
], ids=["DejaVuSans-O", "DejaVuSans-aSgeR", "NimbusSans-OaSgRN", "DejaVuSans-composites", "NimbusSans-accented"])
def test_pen_equals_import_and_analyze(tmp_path, font, chars):
    if not os.path.exists(font):
        pytest.skip(f"{font} is not installed (tools/setup.sh installs it)")
    files = imported(tmp_path, font, chars)
    cmap = ttLib.TTFont(font).getBestCmap()
    pen = pen_splines(font, [cmap[ord(c)] for c in chars])
    assert sorted(pen) == sorted(files) and files
    for name, (path, doc) in files.items():
        assert pen[name] == doc, f"{name}: the pen's spline differs from cmr import's"
        assert cmr.analyze(pen[name]) == cli_json("analyze", path), name


def test_pen_protocol_quadratic_implied_points():
    # A TrueType contour drawn by hand: two off-curve points in a row meet at
    # their implied midpoint (a simple knot, C1); the closing line is implied.
    pen = SplinePen("X", degree=2)
    pen.moveTo((0, 0))
    pen.lineTo((100, 0))
    pen.qCurveTo((150, 0), (150, 100), (100, 100))
    pen.lineTo((0, 100))
    pen.closePath()
    (d,) = pen.splines
    assert d["name"] == "X/c0" and d["degree"] == 2 and d["closed"]
    assert "X/c0/p2" in d["point_names"] and "X/c0/p3" in d["point_names"]
    # An all-off-curve contour (qCurveTo ending in None) is a uniform quadratic.
    pen = SplinePen("Y")
    pen.qCurveTo((0, 0), (10, 0), (10, 10), (0, 10), None)
    pen.closePath()
    (d,) = pen.splines
    assert len(d["points"]) == 4 and d["knots"] == [0, 1, 2, 3, 4]
    assert cmr.analyze(d)["spline"]["cmrwi"] == "none"


def test_pen_cubic_line_inner_points_are_exact():
    # CFF lines get inner points A + k (B - A), k = 21845/65536 (io/font.cpp).
    pen = SplinePen("L")
    pen.moveTo((0, 0))
    pen.lineTo((300, 600))
    pen.curveTo((300, 700), (100, 700), (0, 650))
    pen.closePath()
    (d,) = pen.splines
    k = 21845 / 65536
    assert d["points"][1] == [k * 300, k * 600]
    assert d["point_names"][:4] == ["L/c0/n0", "L/c0/n0+n1@1/3", "L/c0/n0+n1@2/3", "L/c0/n1"]


def test_check_glyph_findings():
    if not os.path.exists(DEJAVU):
        pytest.skip("DejaVu Sans is not installed")
    glyphs = ttLib.TTFont(DEJAVU).getGlyphSet()
    results = cmr.fonttools.check_glyph(glyphs, "O", require="curvature-extrema-at-nodes")
    assert [r["contour"] for r in results] == ["O/c0", "O/c1"]
    for r in results:
        assert r["status"] in ("pass", "fail")
        assert (r["status"] == "pass") == (not r["findings"]), r
        for f in r["findings"]:
            assert f["gate"] == "curvature-extrema-at-nodes" and f["message"]
    with pytest.raises(cmr.InputError, match="no such glyph"):
        cmr.fonttools.check_glyph(glyphs, "no-such-glyph")


def test_pen_errors():
    pen = SplinePen("E")
    with pytest.raises(cmr.InputError, match="before moveTo"):
        pen.lineTo((1, 2))
    with pytest.raises(cmr.InputError, match="degree"):
        SplinePen("E", degree=4)


def test_judge_many_equals_report(tmp_path):
    # The pen's contours judged in one call equal cmr report's entries for
    # the same glyphs: status and every gate's violations.
    if not os.path.exists(DEJAVU):
        pytest.skip("DejaVu Sans is not installed")
    require = "extrema-at-nodes,g2-at-smooth-nodes"
    out = tmp_path / "qa"
    run_cmr("report", DEJAVU, "--glyphs", "O,a,S,l", "--require", require, "--no-thumbnails", "--quiet", "--out", out,
            check=False)
    entries = {e["name"]: e for e in json.loads((out / "report.json").read_text())["splines"]}
    glyphs = ttLib.TTFont(DEJAVU).getGlyphSet()
    contours = [c for n in ("O", "a", "S", "l") for c in cmr.fonttools.glyph_contours(glyphs, n)]
    results = cmr.judge_many(contours, require=require)
    assert [r["name"] for r in results] == [c.name for c in contours]
    assert sorted(entries) == sorted(r["name"] for r in results)
    assert {r["status"] for r in results} == {"pass", "fail"}
    for r in results:
        assert r["status"] == entries[r["name"]]["status"], r["name"]
        assert r["gates"] == entries[r["name"]]["gates"], r["name"]


def test_judge_queue_equals_judge_many():
    # Batches submitted to a JudgeQueue come back, in submission order, as
    # judge_many's entries for the same splines; results() may be asked
    # between submissions and then returns everything so far.
    if not os.path.exists(NIMBUS):
        pytest.skip("Nimbus Sans is not installed")
    require = "curvature-extrema-at-nodes,g2-at-smooth-nodes"
    glyphs = ttLib.TTFont(NIMBUS).getGlyphSet()
    per_glyph = [cmr.fonttools.glyph_contours(glyphs, n) for n in ("O", "a", "S", "g", "e", "l", "I", "o")]
    everything = [c for batch in per_glyph for c in batch]
    expected = cmr.judge_many(everything, require=require)
    q = cmr.JudgeQueue(require=require, threads=2)
    q.submit(per_glyph[0])
    first = q.results()
    assert first == expected[:len(per_glyph[0])]
    for batch in per_glyph[1:]:
        q.submit([c.to_dict() for c in batch])  # dicts are taken as well
    assert q.results() == expected
    assert {r["status"] for r in expected} == {"pass", "fail"}
    with pytest.raises(cmr.InputError, match="unknown option 'requires'"):
        cmr.JudgeQueue(requires="cmrwi")
    with pytest.raises(cmr.InputError):
        q.submit([{"degree": 3}])


def test_check_glyphs_equals_check_glyph():
    # The whole-font path (pipelined through a JudgeQueue) gives each
    # contour the status and violations that check_glyph gives it.
    if not os.path.exists(DEJAVU):
        pytest.skip("DejaVu Sans is not installed")
    glyphs = ttLib.TTFont(DEJAVU).getGlyphSet()
    names = ["O", "a", "S", "l", "g", "B"]
    together = cmr.fonttools.check_glyphs(glyphs, names, require="curvature-extrema-at-nodes")
    alone = [r for n in names for r in cmr.fonttools.check_glyph(glyphs, n, require="curvature-extrema-at-nodes")]
    assert [r["contour"] for r in together] == [r["contour"] for r in alone]
    for t, a in zip(together, alone):
        assert t["status"] == a["status"], t["contour"]
        assert t["gates"] == a["report"]["gates"], t["contour"]
