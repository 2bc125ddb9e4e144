#!/usr/bin/env python3
"""Fig. 8 of Yoshida et al. (CAD&A 2024) and a knot sweep, with `import cmr`
(docs/python.md). Run from the repository root after a build:

    PYTHONPATH=build/python /usr/bin/python3 examples/python/fig8_and_sweep.py OUTDIR

Writes OUTDIR/fig8.png (the CMRs of P0..P5 of the uniform cubic of Fig. 8,
P3 moved into its region, both curvature plots) and OUTDIR/sweep.png (P3's
region while knot 3 moves from 2.5 to 3.5, and its area), and checks the
figure's claims: exactly P1, P2, P3 have a CMR in the view, and the moved
curve is certified increasing (exit 1 otherwise).
"""

import sys
from pathlib import Path

try:
    import matplotlib
except ImportError:
    print("matplotlib is not installed (Debian python3-matplotlib): skipped")
    sys.exit(77)

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import cmr  # noqa: E402
import cmr.plot  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]


def main(out):
    out.mkdir(parents=True, exist_ok=True)
    fig8 = cmr.Spline.load(str(ROOT / "examples/figures/fig8.json"))
    size = (360, 360)
    # One view for every point: the command's default view of the spline.
    view = cmr.region_result(fig8, point=0, size=size, mode="cmr", backend="cpu")["summary"]["view"]
    labels = {k: cmr.region(fig8, point=k, size=size, view=view, mode="cmr", backend="cpu")
              for k in range(len(fig8.points))}
    with_region = [k for k, l in labels.items() if np.any((l == 1) | (l == 2))]
    ok = with_region == [1, 2, 3]
    print(f"points with a CMR in the view: {with_region} (Fig. 8a: [1, 2, 3])")
    union = np.zeros(labels[0].shape, dtype=np.uint8)
    for l in labels.values():
        union[l == 1] = 1
        union[(l == 2) & (union == 0)] = 2

    # Fig. 8b: P3 moved to the middle of its region (the pixel farthest inside).
    ys, xs = np.nonzero(labels[3] == 1)
    j, i = int(np.median(ys)), int(np.median(xs))
    x0, y0, x1, y1 = view
    p3 = (x0 + (x1 - x0) * (i + 0.5) / size[0], y1 - (y1 - y0) * (j + 0.5) / size[1])
    d = fig8.to_dict()
    d["points"][3] = list(p3)
    moved = cmr.Spline.from_dict(d)
    verdict = cmr.analyze(moved)["spline"]["cmr"]
    print(f"P3 moved to ({p3[0]:.4f}, {p3[1]:.4f}): cmr {verdict} (Fig. 8b: increasing)")
    ok = ok and verdict == "increasing"

    fig, axes = plt.subplots(2, 2, figsize=(10, 9))
    cmr.plot.region(axes[0, 0], union, view)
    cmr.plot.spline(axes[0, 0], fig8, comb=False)
    axes[0, 0].set_title("(a) CMRs of P0..P5")
    cmr.plot.curvature(axes[0, 1], fig8)
    axes[0, 1].set_title("(a) curvature: " + cmr.analyze(fig8)["spline"]["cmr"])
    cmr.plot.region(axes[1, 0], labels[3], view)
    cmr.plot.spline(axes[1, 0], moved, comb=True)
    axes[1, 0].set_title("(b) P3 moved within its CMR, with the comb")
    cmr.plot.curvature(axes[1, 1], moved)
    axes[1, 1].set_title("(b) curvature: " + verdict)
    fig.suptitle("Fig. 8: CMRs of a cubic B-spline with knots [0,1,2,3,4,5,6,7] (cmr in Python)")
    fig.tight_layout()
    fig.savefig(out / "fig8.png", dpi=80)
    plt.close(fig)

    # A knot sweep: P3's CMRWI while knot 3 moves (the control points stay).
    values = np.linspace(2.5, 3.5, 5)
    sweep_view = (-1.0, -6.0, 4.0, -1.0)
    pixel_area = (sweep_view[2] - sweep_view[0]) * (sweep_view[3] - sweep_view[1]) / (200 * 200)
    fig, axes = plt.subplots(1, len(values) + 1, figsize=(3.2 * (len(values) + 1), 3.4))
    areas = []
    for ax, u in zip(axes, values):
        s = cmr.knots.set(fig8, 3, float(u))
        l = cmr.region(s, point=3, size=(200, 200), view=sweep_view, backend="cpu")
        areas.append(float(np.count_nonzero((l == 1) | (l == 2))) * pixel_area)
        cmr.plot.region(ax, l, sweep_view, legend=False)
        cmr.plot.spline(ax, s, comb=False, names=False)
        ax.set_xlim(sweep_view[0], sweep_view[2])
        ax.set_ylim(sweep_view[1], sweep_view[3])
        ax.set_title(f"knot 3 = {u:.2f}")
        print(f"knot 3 = {u:.2f}: P3's CMRWI area {areas[-1]:.4f} (pixels x pixel area)")
    axes[-1].plot(values, areas, "o-")
    axes[-1].set_xlabel("knot 3")
    axes[-1].set_ylabel("area of P3's CMRWI")
    fig.tight_layout()
    fig.savefig(out / "sweep.png", dpi=80)
    plt.close(fig)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(Path(sys.argv[1] if len(sys.argv) > 1 else "out/python")))
