#!/usr/bin/python3
"""Why round shapes need their nodes moved (docs/fix.md, "What is left"): exact rational checks, without cmr.

    quarter_arc_check.py

A cubic quarter arc from a node with a horizontal tangent to one with a
vertical tangent, (0, 0), (a, 0), (X, Y - b), (X, Y) with handle lengths
a, b > 0, is how fonts draw a bowl between extremes (URW Gothic's O,
P052's P). With the nodes and their tangents held, only a and b move.

 1. Spanning a square (X = Y = 1): for each of 3600 pairs (a, b) in
    (0, 3] x (0, 3], lambda (exact_glif_check.py's, the rational judge)
    takes both signs, so the curvature has an extremum inside: no handle
    lengths give it monotone curvature.
 2. Nearly square (X = 315, Y = 305, URW Gothic O's counter is 315 x 316):
    none of the handle lengths 100, 106, ..., 256 either.
 3. A little less round (X = 315, Y = 300): a = 190, b = 154 has monotone
    curvature (lambda of one sign).

So a fix of such a bowl moves its nodes to make it less round by several
units, which the glyph fix's searches (nodes held, or a cell each way) do
not reach. Prints one line per check and exits 1 when one fails.
"""
import os
import sys
from fractions import Fraction as F

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from exact_glif_check import monotone, not_monotone  # noqa: E402


def quarter(a, b, x, y):
    return [(F(0), F(0)), (F(a), F(0)), (F(x), F(y) - F(b)), (F(x), F(y))]


unit_pairs = [(F(i, 20), F(j, 20)) for i in range(1, 61) for j in range(1, 61)]
lengths = range(100, 257, 6)
results = [
    (all(not_monotone(quarter(a, b, 1, 1)) for a, b in unit_pairs),
     "a square quarter: an extremum inside for every one of %d handle pairs in (0, 3]^2" % len(unit_pairs)),
    (all(not_monotone(quarter(a, b, 315, 305)) for a in lengths for b in lengths),
     "a 315 x 305 quarter: an extremum inside for every one of %d handle pairs 100..256" % len(lengths) ** 2),
    (monotone(quarter(190, 154, 315, 300)), "a 315 x 300 quarter with a = 190, b = 154: monotone"),
]
for ok, what in results:
    print(("ok   " if ok else "FAIL ") + what)
sys.exit(0 if all(ok for ok, _ in results) else 1)
