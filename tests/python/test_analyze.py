"""cmr.analyze and cmr.segments equal `cmr analyze` / `cmr segments` (same
keys, same numbers) on Fig. 8, 20 seeded random splines, a long spline (the
streamed path) and a space curve."""

import json
import random

import numpy as np
import pytest

import cmr
from conftest import ROOT, cli_json


def random_spline(seed):
    """A seeded random planar spline file: degree 2..5, open or closed, with
    repeated knots and, for every third seed, weights."""
    rng = random.Random(seed)
    degree = rng.randint(2, 5)
    closed = seed % 5 == 4
    m = rng.randint(degree + 1, degree + 7)
    points = [[round(rng.uniform(-10, 10), 3), round(rng.uniform(-10, 10), 3)] for _ in range(m)]
    doc = {"name": f"random {seed}", "degree": degree, "points": points}
    if closed:
        doc["closed"] = True
        knots, u = [0.0], 0.0
        for _ in range(m):
            u += rng.choice([0.5, 1.0, 1.0, 2.0])
            knots.append(u)
    else:
        count = m + degree - 1
        knots, u = [], 0.0
        while len(knots) < count:
            knots.extend([u] * min(rng.choice([1, 1, 1, 2, degree]), count - len(knots)))
            u += rng.choice([0.5, 1.0, 1.5])
        if knots[degree - 1] == knots[m - 1]:
            knots = [float(i) for i in range(count)]
    doc["knots"] = knots
    if seed % 3 == 2:
        doc["weights"] = [round(rng.uniform(0.5, 2.0), 3) for _ in range(m)]
    return doc


def test_fig8_equals_cli(fig8_path):
    cli = cli_json("analyze", fig8_path)
    assert cmr.analyze(str(fig8_path)) == cli
    assert cmr.analyze(json.loads(fig8_path.read_text())) == cli
    assert cmr.analyze(cmr.Spline.load(str(fig8_path))) == cli
    # Options as the command's flags.
    assert cmr.analyze(fig8_path, split=2, mode="cmr", depth=8) == cli_json(
        "analyze", fig8_path, "--split", "2", "--mode", "cmr", "--depth", "8")


@pytest.mark.parametrize("seed", range(20))
def test_seeded_spline_equals_cli(tmp_path, seed):
    doc = random_spline(seed)
    path = tmp_path / f"random{seed}.json"
    path.write_text(json.dumps(doc))
    cli = cli_json("analyze", path)
    assert cmr.analyze(doc) == cli, f"seed {seed}"
    spline = cmr.Spline(doc["degree"], np.array(doc["points"]), knots=doc["knots"], weights=doc.get("weights"),
                        closed=doc.get("closed", False), name=doc["name"])
    assert cmr.analyze(spline) == cli, f"seed {seed} through cmr.Spline"
    n = spline.segment_count
    if n >= 3 and not doc.get("closed"):
        s = n // 2
        assert cmr.analyze(doc, split=s, depth=6) == cli_json("analyze", path, "--split", s, "--depth", 6)
        assert cmr.analyze(doc, segments=(1, n - 1)) == cli_json("analyze", path, "--segments", f"1..{n - 1}")
        assert cmr.analyze(doc, each_piece=True) == cli_json("analyze", path, "--each-piece")
    assert cmr.segments(doc) == cli_json("segments", path), f"seed {seed}"


def test_long_spline_streamed_equals_cli(tmp_path):
    # More spans than the module analyses inline: analyze_on_threads on the
    # worker thread, its dict against the command's streamed text.
    rng = random.Random(7)
    m = 700
    doc = {"degree": 3, "knots": list(range(m + 2)),
           "points": [[i + rng.uniform(-0.3, 0.3), rng.uniform(-1, 1)] for i in range(m)]}
    path = tmp_path / "long.json"
    path.write_text(json.dumps(doc))
    assert cmr.Spline.from_dict(doc).segment_count > 256
    assert cmr.analyze(doc) == cli_json("analyze", path)


@pytest.mark.parametrize("doc", [
    # A zero tangent at the joint (a repeated point): its angle and both
    # curvatures are NaN, which the command prints as null.
    {"degree": 2, "points": [[0, 0], [1, 1], [1, 1], [2, 0]], "knots": [0, 1, 2, 3, 4]},
    # A closed spline with its seam, and the short path (at most 16 spans,
    # the GIL held) against a few more spans.
    {"degree": 3, "points": [[0, 0], [2, 0], [3, 2], [1, 3], [-1, 2]], "closed": True},
    {"degree": 3, "points": [[i, (i * 7) % 5] for i in range(20)], "knots": list(range(22))},
], ids=["zero-tangent", "closed", "17-spans"])
def test_marked_documents_equal_cli(tmp_path, doc):
    path = tmp_path / "s.json"
    path.write_text(json.dumps(doc))
    cli = cli_json("analyze", path)
    assert cmr.analyze(doc) == cli
    assert cmr.analyze(cmr.Spline.from_dict(doc)) == cli


def test_space_curve_equals_cli():
    path = ROOT / "examples" / "space" / "fig8_lifted.json"
    s = cmr.Spline.load(str(path))
    assert s.dimension == 3 and s.points.shape[1] == 3
    assert cmr.analyze(s) == cli_json("analyze", path)
    assert cmr.analyze(s, torsion=True) == cli_json("analyze", path, "--torsion")


def test_spline_round_trip(fig8_path):
    doc = json.loads(fig8_path.read_text())
    s = cmr.Spline.from_dict(doc)
    again = cmr.Spline.from_dict(s.to_dict())
    assert np.array_equal(again.points, s.points) and again.knots == s.knots and again.degree == 3
    assert s.points.dtype == np.float64 and s.points.shape == (len(doc["points"]), 2)
