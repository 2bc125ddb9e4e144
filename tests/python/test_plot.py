"""cmr.plot draws on matplotlib Axes (Agg): region labels in the legend's
colours of cmr region --png, the curve and its comb, kappa(t) with the
report's extrema."""

import numpy as np
import pytest

import cmr
from conftest import ROOT

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import cmr.plot  # noqa: E402

FIG8 = str(ROOT / "examples/figures/fig8.json")


def test_region_colours_are_the_legends():
    colours = cmr.plot.legend_colours()
    assert colours[0][1] == (1.0, 1.0, 1.0) and colours[3][1] == (1.0, 1.0, 1.0)  # not monotone, undecided: white
    r, g, b = colours[1][1]
    assert r > g and r > b  # increasing: red
    r, g, b = colours[2][1]
    assert b > r and b > g  # decreasing: blue
    split = cmr.plot.legend_colours(split=True)
    assert set(split) == {0, 1, 2, 3, 4, 5}
    labels = cmr.region(FIG8, point=3, size=(40, 30), backend="cpu")
    view = cmr.region_result(FIG8, point=3, size=(40, 30), backend="cpu")["summary"]["view"]
    fig, ax = plt.subplots()
    cmr.plot.region(ax, labels, view)
    image = ax.get_images()[0].get_array()
    assert image.shape == (30, 40, 3)
    for code in np.unique(labels):
        assert np.allclose(image[labels == code], colours[int(code)][1])
    assert [t.get_text() for t in ax.get_legend().get_texts()] == [colours[int(c)][0] for c in np.unique(labels)]
    plt.close(fig)


def test_spline_comb_and_curvature():
    s = cmr.Spline.load(FIG8)
    fig, (a, b) = plt.subplots(1, 2)
    cmr.plot.spline(a, s, comb=True)
    assert len(a.get_lines()) > 10  # curve, polygon, comb teeth and outline
    cmr.plot.curvature(b, s)
    # Spline.curvature is det(C', C'') / |C'|^3 of Spline.derivative, and
    # Spline.evaluate's difference quotient is C'.
    t = np.linspace(s.domain[0] + 0.01, s.domain[1] - 0.01, 9)
    d1, d2 = s.derivative(t, 1), s.derivative(t, 2)
    kappa = (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.hypot(d1[:, 0], d1[:, 1]) ** 3
    assert np.allclose(s.curvature(t), kappa, rtol=1e-9, atol=1e-12)
    h = 1e-6
    assert np.allclose((s.evaluate(t + h) - s.evaluate(t - h)) / (2 * h), d1, rtol=1e-6, atol=1e-6)
    extrema = cmr.judge(s)["curvature"]["extrema"]
    dots = [l for l in b.get_lines() if l.get_marker() == "o"]
    assert len(dots) == len(extrema) > 0
    plt.close(fig)
