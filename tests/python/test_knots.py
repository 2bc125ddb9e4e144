"""cmr.knots.* and cmr.kcurve equal `cmr knots` and `cmr kcurve`."""

import json

import numpy as np
import pytest

import cmr
from conftest import ROOT, cli_json


@pytest.mark.parametrize("op,args,call", [
    ("insert", ["2.5"], lambda s: cmr.knots.insert(s, 2.5)),
    ("insert", ["3.25", "--times", "2"], lambda s: cmr.knots.insert(s, 3.25, times=2)),
    ("refine", [], cmr.knots.refine),
    ("elevate", [], cmr.knots.elevate),
    ("clamp", [], cmr.knots.clamp),
    ("uniform", [], cmr.knots.uniform),
    ("set", ["4", "3.5"], lambda s: cmr.knots.set(s, 4, 3.5)),
])
def test_knot_operation_equals_cli(fig8_path, op, args, call):
    assert call(cmr.Spline.load(str(fig8_path))).to_dict() == cli_json("knots", fig8_path, op, *args)


def test_remove_undoes_insert(tmp_path, fig8_path):
    s = cmr.Spline.load(str(fig8_path))
    inserted = cmr.knots.insert(s, 3.5)
    path = tmp_path / "inserted.json"
    path.write_text(json.dumps(inserted.to_dict()))
    removed = cmr.knots.remove(inserted, 3.5)
    assert removed.to_dict() == cli_json("knots", path, "remove", "3.5")
    assert np.allclose(removed.points, s.points, atol=1e-12)


def test_kcurve_equals_cli(tmp_path):
    for path in sorted((ROOT / "examples" / "kcurve").glob("*.json")):
        doc = json.loads(path.read_text())
        if set(doc) - {"points", "closed"}:
            continue
        spline = cmr.kcurve(np.array(doc["points"], dtype=float), closed=doc.get("closed", False))
        assert spline.to_dict() == cli_json("kcurve", path), path.name
        cubic = cmr.kcurve(doc["points"], closed=doc.get("closed", False), cubic=True)
        assert cubic.to_dict() == cli_json("kcurve", path, "--cubic"), path.name
