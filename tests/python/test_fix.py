"""cmr.fix: a certified repair, re-judged by cmr.analyze and by the cmr
program, and the same move as `cmr fix`."""

import json

import numpy as np
import pytest

import cmr
from conftest import ROOT, cli_json


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
