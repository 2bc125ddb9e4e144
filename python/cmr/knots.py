"""``cmr knots FILE OP``: knot operations, each returning a new cmr.Spline
(docs/knots.md). insert, refine, clamp and elevate keep the curve; remove
keeps it within `tol`; set and uniform change it."""

from . import _options as _o
from ._cmr import _knots


def insert(spline, u, times=1):
    """Inserts knot u `times` times (multiplicity stays <= degree)."""
    return _knots(_o.spline(spline, "knots.insert"), "insert", _o.number("u", u), _o.integer("times", times, 1, _o.MAX_DEGREE),
                  None, 0)


def remove(spline, u, tol=None):
    """Removes one copy of the interior knot u if the curve moves by <= tol
    (absolute; default 1e-9 x the control points' extent)."""
    return _knots(_o.spline(spline, "knots.remove"), "remove", _o.number("u", u), 1,
                  None if tol is None else _o.number("tol", tol, 0.0), 0)


def set(spline, index, u):  # noqa: A001 (the command's name)
    """Sets knot `index` to u (order and multiplicity are checked)."""
    return _knots(_o.spline(spline, "knots.set"), "set", _o.number("u", u), 1, None, _o.integer("index", index, 0))


def clamp(spline):
    """End knots of multiplicity degree (the same curve on its domain)."""
    return _knots(_o.spline(spline, "knots.clamp"), "clamp", 0.0, 1, None, 0)


def uniform(spline):
    """Knots 0, 1, 2, ... with the same control points (the curve changes)."""
    return _knots(_o.spline(spline, "knots.uniform"), "uniform", 0.0, 1, None, 0)


def elevate(spline):
    """Raises the degree by one (the same curve)."""
    return _knots(_o.spline(spline, "knots.elevate"), "elevate", 0.0, 1, None, 0)


def refine(spline):
    """Inserts the midpoint of every segment (the same curve)."""
    return _knots(_o.spline(spline, "knots.refine"), "refine", 0.0, 1, None, 0)
