"""Bad input raises cmr.InputError (a ValueError) with one clear line and
never crashes the interpreter; the spline fuzzer's corpus, mutated, goes
through the dict reader."""

import json
import math
import random
import subprocess
import sys

import numpy as np
import pytest

import cmr
from conftest import ROOT

FIG8 = json.loads((ROOT / "examples/figures/fig8.json").read_text())


def one_line(excinfo):
    message = str(excinfo.value)
    assert message and "\n" not in message, repr(message)
    return message


def test_error_types():
    assert issubclass(cmr.InputError, ValueError)
    assert issubclass(cmr.EnvironmentError, OSError)


@pytest.mark.parametrize("points,match", [
    (np.zeros((4, 5)), r"points: expected an N x 2 or N x 3 array, got shape \(4, 5\)"),
    (np.zeros(6), r"got shape \(6,\)"),
    (np.zeros((2, 3, 2)), r"got shape \(2, 3, 2\)"),
    ([[0, 0], [1, 1, 1], [2, 0], [3, 1]], "3 coordinates"),
    ([[0, 0], [1, "x"], [2, 0], [3, 1]], r"points\[1\]\[1\] is not a number"),
    ([[0, 0], [1, math.nan], [2, 0], [3, 1]], r"points\[1\]\[1\] is not a finite number"),
    (np.array([[0, 0], [1, np.inf], [2, 0], [3, 1]]), r"points\[1\]\[1\] is not a finite number"),
    (np.array([["a", "b"]] * 4), "is not numbers"),
])
def test_bad_points(points, match):
    with pytest.raises(cmr.InputError, match=match) as e:
        cmr.Spline(3, points, knots=[0, 0, 0, 1, 1, 1])
    one_line(e)


def test_bad_knots_and_degree():
    pts = FIG8["points"]
    with pytest.raises(cmr.InputError, match="knots") as e:
        cmr.Spline(3, pts, knots=[0, 1, 2])  # wrong count
    one_line(e)
    with pytest.raises(cmr.InputError, match=r"knots\[4\]") as e:
        cmr.Spline(3, pts, knots=[0, 1, 2, 3, 2.5, 5, 6, 7])
    one_line(e)
    with pytest.raises(cmr.InputError, match="knots") as e:
        cmr.Spline(3, pts, knots=[0, 1, 2, 3, math.nan, 5, 6, 7])
    one_line(e)
    with pytest.raises(cmr.InputError, match="degree") as e:
        cmr.Spline(2.5, pts, knots=FIG8["knots"])
    one_line(e)
    with pytest.raises(cmr.InputError) as e:
        cmr.Spline(3, pts, knots=FIG8["knots"], weights=[1, 2])
    assert "weights" in one_line(e)


@pytest.mark.parametrize("value,match", [
    (42, "expected a cmr.Spline, a spline-file dict or a file path, got int"),
    ([1, 2, 3], "got list"),
    ({"points": FIG8["points"], "degree": 3, "knots": FIG8["knots"], "colour": 1}, "colour"),
    ({"points": FIG8["points"], "degree": 3, "knots": FIG8["knots"], "name": object()}, "not a spline-file value"),
    ({1: 2}, "a key that is not a string"),
    ({"degree": 3, "points": [[0, 0], [1, 1], [2, 0], [3, [[[[[[[[[[1]]]]]]]]]]]]}, r"points\[3\]\[1\] is not a number"),
    ("/no/such/file.json", "cannot open"),
])
def test_bad_spline_values(value, match):
    with pytest.raises(cmr.InputError, match=match) as e:
        cmr.analyze(value)
    one_line(e)


def test_deep_nesting_is_refused_not_a_crash():
    # 100,000 nested lists: read recursively, they would exhaust the C
    # stack; the reader refuses past 64 levels.
    deep = []
    for _ in range(100000):
        deep = [deep]
    for value in ({"degree": 3, "points": deep}, {"degree": 3, "points": [[0, 0]], "name": {"a": deep}}):
        with pytest.raises(cmr.InputError, match="nested more than 64 deep") as e:
            cmr.analyze(value)
        one_line(e)


@pytest.mark.parametrize("call,match", [
    (lambda: cmr.analyze(FIG8, dept=3), "analyze: unknown option 'dept'"),
    (lambda: cmr.analyze(FIG8, depth=99), "depth: 99 is outside 0..30"),
    (lambda: cmr.analyze(FIG8, depth="3"), "depth: expected an integer, got str"),
    (lambda: cmr.analyze(FIG8, depth=True), "depth: expected an integer, got bool"),
    (lambda: cmr.analyze(FIG8, mode="max"), "mode: 'max' is not one of cmrwi, cmr"),
    (lambda: cmr.analyze(FIG8, split=7), "split"),
    (lambda: cmr.analyze(FIG8, segments=(2, 9)), "segments"),
    (lambda: cmr.analyze(FIG8, split=1, each_piece=True), "each_piece takes the joints itself"),
    (lambda: cmr.analyze(FIG8, angle_tol=math.nan), "angle_tol: nan is not a finite number"),
    (lambda: cmr.region(FIG8, point=3, size=(0, 10)), r"size\[0\]: 0 is outside 1..16384"),
    (lambda: cmr.region(FIG8, point=3, size=(10, 10), view=(0, 0, 0, 1)), "view"),
    (lambda: cmr.region(FIG8, point=99, size=(8, 8)), "99"),
    (lambda: cmr.region(FIG8, size=(8, 8)), "point is required"),
    (lambda: cmr.region(FIG8, point=3, backend="gpu"), "backend: 'gpu' is not one of auto, vulkan, cpu"),
    (lambda: cmr.region(FIG8, point=3, colour="red"), "region: unknown option 'colour'"),
    (lambda: cmr.fix(FIG8, require="smooth"), "smooth"),
    (lambda: cmr.fix(FIG8, require="cmrwi", max_move=-1), "max_move"),
    (lambda: cmr.fix(FIG8, require="cmrwi", grid=2), r"grid: 2 is outside 8..512"),
    (lambda: cmr.knots.insert(FIG8, 99), "99"),
    (lambda: cmr.knots.insert(FIG8, "x"), "u: expected a number, got str"),
    (lambda: cmr.kcurve([[0, 0], [1, 1]], tolerance=2), r"tolerance: 2.0 is outside \(0, 1\)"),
    (lambda: cmr.kcurve([[0, 0], [1, math.nan], [2, 0]]), r"points\[1\]\[1\] is not a finite number"),
    (lambda: cmr.kcurve(np.zeros((3, 3))), r"points\[0\] is not an \[x, y\] pair"),
    (lambda: cmr.segments(cmr.Spline.load(str(ROOT / "examples/space/fig8_lifted.json"))), "space curve"),
    (lambda: cmr.report([ROOT / "examples/space/fig8_lifted.json"]), "is a space curve: cmr.report takes planar"),
])
def test_bad_options(call, match):
    with pytest.raises(cmr.InputError, match=match) as e:
        call()
    one_line(e)


def mutations(doc, rng):
    """Seeded mutations of a spline-file dict: wrong types, NaN and
    infinities, wrong lengths and shapes, missing and unknown keys."""
    bad_values = [None, "x", math.nan, math.inf, -math.inf, [], {}, [[]], True, 1e308, -1, 0, 2.5, [1, 2, 3],
                  np.zeros((2, 5)), np.array([math.nan, 1.0]), 10 ** 30, "", [None]]
    d = json.loads(json.dumps(doc))
    for _ in range(rng.randint(1, 3)):
        key = rng.choice(sorted(set(d) | {"degree", "knots", "points", "weights", "closed", "name", "extra"}))
        r = rng.random()
        if r < 0.25:
            d.pop(key, None)
        elif r < 0.5:
            d[key] = rng.choice(bad_values)
        elif key in d and isinstance(d[key], list) and d[key]:
            lst = d[key]
            i = rng.randrange(len(lst))
            if r < 0.7:
                lst[i] = rng.choice(bad_values)
            elif r < 0.85:
                del lst[i]
            else:
                lst.insert(i, lst[i])
        else:
            d[key] = rng.choice(bad_values)
    return d


def test_fuzz_corpus_dicts():
    # The spline fuzzer's corpus (fuzz/corpus/spline_json: bytes after a
    # first byte that picks the knot convention), each seed mutated 150 times.
    rng = random.Random(38)
    seeds = []
    for path in sorted((ROOT / "fuzz" / "corpus" / "spline_json").iterdir()):
        data = path.read_bytes()
        for text in (data, data[1:]):
            try:
                seeds.append(json.loads(text))
                break
            except ValueError:
                continue
    assert len(seeds) >= 5
    outcomes = {"valid": 0, "InputError": 0}
    for seed in seeds:
        for _ in range(150):
            d = mutations(seed, rng)
            try:
                s = cmr.Spline.from_dict(d)
            except cmr.InputError as e:
                assert "\n" not in str(e) and str(e), (d, str(e))
                outcomes["InputError"] += 1
                continue
            outcomes["valid"] += 1
            if s.dimension == 2:
                cmr.analyze(s, depth=4)
    assert outcomes["valid"] > 0 and outcomes["InputError"] > 0, outcomes


def test_interpreter_survives_bad_input_in_a_subprocess():
    # Whatever goes wrong must come back as an exception, never a crash: a
    # child interpreter runs a batch of bad calls and must exit 0.
    code = (
        "import math, numpy as np, cmr\n"
        "bad = [lambda: cmr.Spline(3, np.zeros((0, 2))), lambda: cmr.Spline(-1, [[0, 0]]),\n"
        "       lambda: cmr.Spline(40, np.zeros((41, 2))), lambda: cmr.analyze({'points': [[0, 0]] * 3}),\n"
        "       lambda: cmr.region({'points': [[0, 0], [1, 1], [2, 0]]}, point=1, size=(4, 4), backend='cpu'),\n"
        "       lambda: cmr.knots.remove({'points': [[0, 0], [1, 1], [2, 0]]}, 0.5)]\n"
        "for f in bad:\n"
        "    try:\n"
        "        f()\n"
        "    except cmr.InputError:\n"
        "        pass\n"
    )
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
