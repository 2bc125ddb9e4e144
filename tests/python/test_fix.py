"""cmr.fix: a certified repair, re-judged by cmr.analyze and by the cmr
program, and the same move as `cmr fix`."""

import json

import numpy as np
import pytest

import cmr
from conftest import ROOT, cli_json, run_cmr


def test_fix_fig8_cmrwi_is_rejudged_monotone(tmp_path, fig8_path):
    before = cmr.analyze(fig8_path)
    assert before["spline"]["cmrwi"] == "none"
    result = cmr.fix(fig8_path, require="cmrwi")
    assert isinstance(result.spline, cmr.Spline) and result.moves
    # Re-judged here (the certified analysis, exact where the bound does not decide) ...
    after = cmr.analyze(result.spline)
    assert after["spline"]["cmrwi"] in ("increasing", "decreasing"), after["spline"]
    assert result.certificate["holds"] and result.certificate["cmrwi"] == after["spline"]["cmrwi"]
    # ... and by the cmr program on the written file.
    path = tmp_path / "fixed.json"
    path.write_text(json.dumps(result.spline.to_dict()))
    assert cli_json("analyze", path)["spline"]["cmrwi"] == after["spline"]["cmrwi"]
    # Only the moved points moved, by the reported displacement.
    moved = {m["point"]: m for m in result.moves}
    p0, p1 = cmr.Spline.load(str(fig8_path)).points, result.spline.points
    for k in range(len(p0)):
        if k in moved:
            assert np.allclose(p1[k], moved[k]["to"]) and np.allclose(p1[k] - p0[k], moved[k]["displacement"])
        else:
            assert np.array_equal(p0[k], p1[k]), k


def test_fix_equals_cli(fig8_path):
    cli = cli_json("fix", fig8_path, "--require", "cmrwi", "--points", "2")
    doc = cmr.fix(fig8_path, require="cmrwi", points=[2]).document
    assert "file" not in doc
    for key in ("require", "segments", "keep", "already", "fixed", "moves", "total_squared", "max_distance", "size",
                "tolerance", "failing_segments", "tie_joints", "units", "certificate"):
        assert doc[key] == cli[key], key


def test_fix_nothing_to_do_and_no_fix(fig8_path):
    fixed = cmr.fix(fig8_path, require="cmrwi").spline
    again = cmr.fix(fixed, require="cmrwi")
    assert again.document["already"] and again.moves == []
    with pytest.raises(cmr.InputError, match="no certified fix"):
        cmr.fix(fig8_path, require="cmrwi", max_move=1e-9)


def test_space_fix_equals_cli_and_is_rejudged():
    path = ROOT / "examples/space/fig8_lifted.json"
    assert cmr.analyze(path)["spline"]["curvature"] == "none"
    cli = cli_json("fix", path, "--points", "2")
    r = cmr.fix(path, points=[2])
    assert r.spline.dimension == 3 and r.document["dimension"] == 3
    for key in ("require", "keep", "already", "fixed", "moves", "total_squared", "max_distance", "size", "tolerance",
                "failing_segments", "joint_conflicts", "tie_joints", "units", "certificate"):
        assert r.document[key] == cli[key], key
    # Re-judged exactly (analyze_space, as cmr analyze).
    assert cmr.analyze(r.spline)["spline"]["curvature"] in ("increasing", "decreasing")
    with pytest.raises(cmr.InputError, match="its fix takes require cmr"):
        cmr.fix(path, require="split:2")


# fix_glyph: a UFO glyph on the grid, the command's answer, and the .glif written back.
SANS = ROOT / "examples" / "ufo" / "Sans.ufo"
SIDES = ["c0/p2", "c0/p4", "c0/p8", "c0/p10", "c1/p2", "c1/p4", "c1/p8", "c1/p10"]


def test_fix_glyph_equals_cli_and_keeps_to_the_named_points():
    doc = cmr.fix_glyph(SANS, "o", require="curvature-extrema-at-nodes", points=SIDES)
    cli = cli_json("fix", SANS, "--glyph", "o", "--require", "curvature-extrema-at-nodes", "--points", ",".join(SIDES))
    assert doc["contours"] == cli["contours"]
    assert doc["points"] == ["o/" + p for p in SIDES]
    moves = [m for c in doc["contours"] for m in c["moves"]]
    assert moves and {m["point"] for m in moves} <= {"o/" + p for p in SIDES}
    assert all(float(v).is_integer() for m in moves for v in m["to"])
    assert all(x["after"] == 0 for c in doc["contours"] for x in c["rejudged"])
    # "source" is the .glif's contour and point: the name's numbers
    for m in moves:
        c, p = m["source"]
        assert m["point"] == f"o/c{c}/p{p}"


def test_fix_glyph_in_place_changes_only_the_moved_points(tmp_path):
    import shutil
    ufo = tmp_path / "Sans.ufo"
    shutil.copytree(SANS, ufo)
    glif = ufo / "glyphs" / "o.glif"
    before = glif.read_text().split("\n")
    doc = cmr.fix_glyph(ufo, "o", points="c0/p2,c0/p4,c0/p8,c0/p10,c1/p2,c1/p4,c1/p8,c1/p10", in_place=True)
    after = glif.read_text().split("\n")
    assert doc["written"] == str(glif)
    changed = [(a, b) for a, b in zip(before, after) if a != b]
    assert len(before) == len(after) and len(changed) == sum(len(c["moves"]) for c in doc["contours"])
    for a, b in changed:
        assert "<point" in a and a.split('x="')[0] == b.split('x="')[0] and a.split('"', 4)[4] == b.split('"', 4)[4]
    assert (ufo / "glyphs" / "O_.glif").read_text() == (SANS / "glyphs" / "O_.glif").read_text()


def test_fix_glyphs_equals_cli_and_lists_a_glyph_without_a_fix():
    # cmr.fix_glyphs is `cmr fix UFO --glyphs SPEC`: the same document. Under
    # g2 alone O and o pass as they are, and s has no fix: it is listed with
    # its reason, not raised. (A search that ends in little work, so that no
    # time guard can end either run first on a loaded machine.)
    # A reason names an option as each front end spells it (--work, work).
    doc = cmr.fix_glyphs(SANS, "all", require="g2-at-smooth-nodes")
    p = run_cmr("fix", SANS, "--glyphs", "all", "--require", "g2-at-smooth-nodes", check=False)
    assert p.returncode == 1 and doc == json.loads(p.stdout.replace("a larger --work", "a larger work"))
    assert doc["summary"]["judged"] == 3 and doc["summary"]["already"] == 2 and doc["summary"]["unfixed"] == 1
    assert [(g["glyph"], g["fixed"]) for g in doc["glyphs"]] == [("s", False)] and doc["glyphs"][0]["reason"]
    assert cmr.fix_glyphs(SANS, "all", require="g2-at-smooth-nodes", strict=True) == json.loads(
        run_cmr("fix", SANS, "--glyphs", "all", "--require", "g2-at-smooth-nodes", "--strict",
                check=False).stdout.replace("a larger --work", "a larger work"))
    with pytest.raises(cmr.InputError, match="min_severity: -1.0 is below 0"):
        cmr.fix_glyphs(SANS, min_severity=-1)


def test_fix_glyphs_in_place_writes_only_the_fixed_glyphs(tmp_path):
    # in_place writes each fixed glyph's .glif (only its moved points' x and
    # y) and no other file.
    import shutil
    ufo = tmp_path / "Sans.ufo"
    shutil.copytree(SANS, ufo)
    doc = cmr.fix_glyphs(ufo, "o", require="curvature-extrema-at-nodes", in_place=True)
    assert doc["summary"]["fixed"] == 1 and doc["written"] == [str(ufo / "glyphs" / "o.glif")]
    assert all(x["after"] == 0 for c in doc["glyphs"][0]["contours"] for x in c["rejudged"])
    for name in ("O_.glif", "o.glif", "s.glif", "contents.plist"):
        same = (ufo / "glyphs" / name).read_text() == (SANS / "glyphs" / name).read_text()
        assert same == (name != "o.glif"), name
    with pytest.raises(cmr.InputError, match="fix_glyphs: unknown option 'points'"):
        cmr.fix_glyphs(SANS, points="p1")
    with pytest.raises(cmr.InputError, match="glyphs selects glyphs of a UFO folder"):
        cmr.fix_glyphs(SANS / "glyphs" / "o.glif")


@pytest.mark.parametrize("kwargs, says", [
    ({"points": ["zz"]}, "points: 'zz' names no point of the glyph o"),
    ({"points": "p2"}, "points: 'p2' names 2 points"),
    ({"grid": -1}, "grid: -1.0 is below 0"),
    ({"require": "g3-at-smooth-nodes"}, "no certified fix for G3"),
    ({"colour": 1}, "fix_glyph: unknown option 'colour'"),
    ({"work": 0}, "work: 0 is outside 1..1000000000"),
    ({"work": 1.5}, "work: expected an integer"),
    ({"add_nodes": True, "grid": 0}, "add_nodes needs the grid \\(grid > 0\\)"),
    ({"add_nodes": True, "points": "c0/p2"}, "add_nodes with points: the named points are the source's"),
])
def test_fix_glyph_bad_requests_are_one_line(kwargs, says):
    with pytest.raises(cmr.InputError, match=says):
        cmr.fix_glyph(SANS, "o", **kwargs)


def test_fix_glyph_out_of_work_says_that_more_work_searches_further():
    # The glyph's budget is work (the same fix on any machine); a glyph that
    # uses all of it without a fix says so, naming the keyword that raises it.
    with pytest.raises(cmr.InputError, match="glyph's work ran out \\(50 units a glyph\\): a larger work searches"):
        cmr.fix_glyph(SANS, "o", work=50)
    assert cmr.fix_glyph(SANS, "o", work=cmr.GLYPH_WORK)["contours"]


def test_fix_glyph_needs_a_glyph_of_the_source():
    with pytest.raises(cmr.InputError, match="name the glyph"):
        cmr.fix_glyph(SANS)
    with pytest.raises(cmr.InputError, match="no glyph named 'Z'"):
        cmr.fix_glyph(SANS, "Z")


def test_fix_glyph_applied_through_ufolib2_passes_the_exact_check(tmp_path):
    # docs/python.md's ufoLib2 script: each move's "source" is the point to set.
    ufoLib2 = pytest.importorskip("ufoLib2")
    import subprocess
    import sys
    doc = cmr.fix_glyph(SANS, "o", require="curvature-extrema-at-nodes", points=SIDES)  # 0.1 s; all points: 7 s
    font = ufoLib2.Font.open(SANS)
    for c in doc["contours"]:
        for m in c["moves"]:
            contour, point = m["source"]
            p = font["o"].contours[contour].points[point]
            assert [p.x, p.y] == m["from"]
            p.x, p.y = m["to"]
    font.save(tmp_path / "Out.ufo")
    check = [sys.executable, str(ROOT / "tests" / "report" / "exact_glif_check.py")]
    before = subprocess.run(check + [str(SANS / "glyphs" / "o.glif"), "--gates", "extrema"], capture_output=True)
    after = subprocess.run(check + [str(tmp_path / "Out.ufo" / "glyphs" / "o.glif"), "--gates", "extrema"],
                           capture_output=True, text=True)
    assert before.returncode == 1 and after.returncode == 0, after.stdout
