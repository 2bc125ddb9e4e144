"""cmr.plot: splines with their curvature combs, region label maps in the
legend's colours, and kappa(t) with its certified extrema, on a matplotlib
Axes (matplotlib is optional: Debian python3-matplotlib; nothing else in cmr
imports it).

    import matplotlib.pyplot as plt, cmr, cmr.plot
    fig, (a, b) = plt.subplots(1, 2)
    labels = cmr.region(s, point=3, view=v, size=(400, 400), backend="cpu")
    cmr.plot.region(a, labels, v); cmr.plot.spline(a, s, comb=True)
    cmr.plot.curvature(b, s)
"""

import numpy as np

from . import _options as _o
from . import judge
from ._cmr import _label_colour

__all__ = ["spline", "region", "curvature", "legend_colours"]

_PLAIN_NAMES = ["not monotone", "increasing", "decreasing", "undecided"]
_SPLIT_NAMES = ["none", "inc-inc", "inc-dec", "dec-inc", "dec-dec", "undecided"]


def legend_colours(split=False):
    """{code: (name, (r, g, b))}: the colours `cmr region --png` gives the
    label codes (draw/draw.hpp: label_colour), plain or split labels."""
    names = _SPLIT_NAMES if split else _PLAIN_NAMES
    return {code: (name, _label_colour(code, split)) for code, name in enumerate(names)}


def _samples(s, per_segment):
    ts = []
    for a, b in s.segment_intervals:
        ts.append(np.linspace(a, b, per_segment))
    return np.concatenate(ts)


def spline(ax, s, *, comb=True, polygon=True, names=True, samples=64, comb_scale=None, color="black"):
    """The curve, its control polygon and point numbers, and its curvature
    comb (the normal scaled by kappa, every fourth sample; comb_scale: world
    units per unit of curvature, default 15% of the curve size over the
    largest |kappa|)."""
    s = _o.spline(s, "plot.spline")
    t = _samples(s, samples)
    xy = s.evaluate(t)
    ax.plot(xy[:, 0], xy[:, 1], color=color, lw=1.5, zorder=3)
    p = s.points
    if polygon:
        ax.plot(p[:, 0], p[:, 1], "o-", color="0.45", lw=0.8, ms=3, zorder=2)
        if names:
            for k, (x, y) in enumerate(p):
                ax.annotate(f"P{k}", (x, y), textcoords="offset points", xytext=(4, 4), fontsize=8, zorder=4)
    if comb:
        kappa = s.curvature(t)
        d = s.derivative(t, 1)
        speed = np.hypot(d[:, 0], d[:, 1])
        ok = np.isfinite(kappa) & (speed > 0)
        normal = np.zeros_like(d)
        normal[ok] = np.stack([-d[ok, 1], d[ok, 0]], axis=1) / speed[ok, None]
        if comb_scale is None:
            size = float(np.hypot(*(p.max(axis=0) - p.min(axis=0))))
            top = float(np.max(np.abs(kappa[ok]))) if ok.any() else 0.0
            comb_scale = 0.15 * size / top if top > 0 else 0.0
        tips = xy + normal * (comb_scale * np.where(ok, kappa, 0.0))[:, None]
        for i in range(0, len(t), 4):
            if ok[i]:
                ax.plot([xy[i, 0], tips[i, 0]], [xy[i, 1], tips[i, 1]], color="tab:green", lw=0.5, zorder=2)
        ax.plot(tips[ok, 0], tips[ok, 1], color="tab:green", lw=0.8, zorder=2)
    ax.set_aspect("equal")
    return ax


def region(ax, labels, view, *, split=False, legend=True):
    """A label array of cmr.region (plain or split codes) over the world
    rectangle view = (x0, y0, x1, y1), in the legend's colours; with legend,
    one patch per label code present."""
    import matplotlib.patches as mpatches
    labels = np.asarray(labels, dtype=np.uint8)
    colours = legend_colours(split)
    rgb = np.ones(labels.shape + (3,))
    for code, (_, c) in colours.items():
        rgb[labels == code] = c
    x0, y0, x1, y1 = view
    ax.imshow(rgb, extent=(x0, x1, y0, y1), origin="upper", interpolation="nearest", zorder=0)
    if legend:
        present = sorted(set(np.unique(labels).tolist()) & set(colours))
        handles = [mpatches.Patch(facecolor=colours[c][1], edgecolor="0.5", label=colours[c][0]) for c in present]
        ax.legend(handles=handles, loc="best", fontsize=8)
    return ax


def curvature(ax, s, *, samples=200, extrema=True, color="black"):
    """kappa(t) over the domain, joints as thin vertical lines, and the
    certified extrema of cmr report (the roots of lambda, and jumps at
    joints) as dots: red a maximum, blue a minimum of signed curvature."""
    s = _o.spline(s, "plot.curvature")
    for a, b in s.segment_intervals:
        t = np.linspace(a, b, samples)
        ax.plot(t, s.curvature(t), color=color, lw=1.2)
        ax.axvline(a, color="0.85", lw=0.6, zorder=0)
    ax.axvline(s.domain[1], color="0.85", lw=0.6, zorder=0)
    if extrema:
        events = judge(s).get("curvature", {}).get("extrema", [])
        for e in events:
            c = "tab:red" if e.get("direction") == "maximum" else "tab:blue"
            ax.plot([e["t"]], [e["kappa"]], "o", color=c, ms=5, zorder=3)
    ax.set_xlabel("t")
    ax.set_ylabel("curvature")
    return ax
