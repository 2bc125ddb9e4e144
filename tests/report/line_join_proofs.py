#!/usr/bin/python3
"""The two line-join proofs of report/glyph_joins.hpp, checked in exact rational arithmetic without cmr's code.

    line_join_proofs.py

A cubic S = (J, H1, H2, F) that leaves a line smoothly at J, under g2 at J
(so H2 on the line too), in coordinates with J = (0, 0) and the line along
y: H1 = (0, a) with a > 0, H2 = (0, c), F = (b, e) with b != 0.

 1. det(P', P'') = -18 b t (a (1 - 2t) + c t), whatever e (polynomial identity).
 2. With r = c - a, q = e - c, N(t) = t (a (1 - 2t) + c t) and D = |P'|^2:
    N'(1) D(1) - 3/2 N(1) D'(1) = 9 (6 r^2 q - (4r + a)(b^2 + q^2)).
 3. held_cubic_line_join: where e <= 0 or 9 e^2 <= 40 b^2, every such cubic
    has a curvature extremum strictly inside: lambda's Bernstein
    coefficients (exact_glif_check.py's, the rational judge) are not of one
    sign class (random rationals, and the bound's edge).
 4. The bound is needed: F = (100, 250) (9 e^2 > 40 b^2) with a = 28,
    c = 177 has monotone curvature (lambda of one sign).
 5. square_cubic_line_join: F = (b, c) (F's tangent square to the line)
    has an extremum inside for every a > 0, b != 0 and c.
 6. held_cubic_line_join_on_grid: for any e, every such cubic with c <= a,
    or with c > a and c >= e, has an extremum inside (random rationals, e
    beyond the bound of 3); so on the integer grid only 1 <= a < c < e
    remain, and for P052 L's serif joins (b = 25, e = 59) each of those
    1653 cubics has an extremum inside too.

Prints one line per check and exits 1 when one fails.
"""
import os
import random
import sys
from fractions import Fraction as F

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from exact_glif_check import deriv, lam, monotone, not_monotone, poly_mul, poly_sub  # noqa: E402

failures = 0


def check(ok, what):
    global failures
    print(("ok   " if ok else "FAIL ") + what)
    failures += 0 if ok else 1


def power(c):
    p0, p1, p2, p3 = c
    return [p0, 3 * (p1 - p0), 3 * (p2 - 2 * p1 + p0), p3 - 3 * p2 + 3 * p1 - p0]


def at(poly, t):
    return sum(c * t ** i for i, c in enumerate(poly))


def cubic(a, c, b, e):
    return [(F(0), F(0)), (F(0), F(a)), (F(0), F(c)), (F(b), F(e))]


rng = random.Random(36)


def rational(lo, hi):
    return F(rng.randint(lo * 64, hi * 64), 64)


# 1 and 2: the identities, on random rationals.
ok1 = ok2 = True
for _ in range(200):
    a, c, b, e = rational(1, 400), rational(-400, 800), rational(-400, 400), rational(-400, 800)
    if a == 0 or b == 0:
        continue
    seg = cubic(a, c, b, e)
    x = power([p[0] for p in seg])
    y = power([p[1] for p in seg])
    x1, y1 = deriv(x), deriv(y)
    x2, y2 = deriv(x1), deriv(y1)
    det12 = poly_sub(poly_mul(x1, y2), poly_mul(y1, x2))
    expected = [F(0), -18 * b * a, -18 * b * (c - 2 * a)]  # -18 b t (a + (c - 2a) t)
    det12 = det12 + [F(0)] * (len(expected) - len(det12))
    ok1 = ok1 and all(u == v for u, v in zip(det12, expected)) and all(u == 0 for u in det12[len(expected):])
    N = [F(0), a, c - 2 * a]
    D = [u + v for u, v in zip(*[p + [F(0)] * (5 - len(p)) for p in (poly_mul(x1, x1), poly_mul(y1, y1))])]
    r, q = c - a, e - c
    lhs = at(deriv(N), 1) * at(D, 1) - F(3, 2) * at(N, 1) * at(deriv(D), 1)
    ok2 = ok2 and lhs == 9 * (6 * r * r * q - (4 * r + a) * (b * b + q * q))
check(ok1, "det(P', P'') = -18 b t (a (1 - 2t) + c t) on 200 random cubics")
check(ok2, "N'(1) D(1) - 3/2 N(1) D'(1) = 9 (6 r^2 q - (4r + a)(b^2 + q^2)) on 200 random cubics")

# 3: held_cubic_line_join's claim, on random rationals inside the bound and at its edge.
checked = bad = 0
while checked < 1500:
    a, c, b = rational(1, 600), rational(-600, 1200), rational(-400, 400)
    if b == 0:
        continue
    # e up to the bound sqrt(40)/3 |b| (just inside: 9 e^2 <= 40 b^2), or e <= 0
    e = rng.choice([rational(-600, 0), F(rng.randint(0, 2108), 1000) * abs(b)])
    if not (e <= 0 or 9 * e * e <= 40 * b * b):
        continue
    checked += 1
    bad += 0 if not_monotone(cubic(a, c, b, e)) else 1
for b, e in ((F(168), F(179)), (F(3), F(6)), (F(100), F(210)), (F(-50), F(105))):
    for a in (F(1), F(28), F(118), F(400)):
        for c in (F(-100), F(0), a, F(177), F(205), e - 1, F(900)):
            checked += 1
            bad += 0 if not_monotone(cubic(a, c, b, e)) else 1
check(bad == 0, "held line end: an extremum inside every one of %d cubics with e <= 0 or 9 e^2 <= 40 b^2" % checked)

# 4: beyond the bound the claim is false.
check(monotone(cubic(28, 177, 100, 250)), "F = (100, 250), a = 28, c = 177: monotone (the bound is needed)")

# 5: square_cubic_line_join's claim.
checked = bad = 0
while checked < 800:
    a, c, b = rational(1, 600), rational(-600, 1200), rational(-400, 400)
    if b == 0:
        continue
    checked += 1
    bad += 0 if not_monotone(cubic(a, c, b, c)) else 1
check(bad == 0, "square far tangent: an extremum inside every one of %d cubics F = (b, c)" % checked)

# 6: held_cubic_line_join_on_grid's claims.
checked = bad = 0
while checked < 800:
    a, b = rational(1, 600), rational(-400, 400)
    if b == 0:
        continue
    e = F(rng.randint(2109, 20000), 1000) * abs(b)  # beyond the bound: 9 e^2 > 40 b^2
    c = rng.choice([rational(-600, 0) + a, a - rational(0, 600), e + rational(0, 600)])  # c <= a, or c >= e
    checked += 1
    bad += 0 if not_monotone(cubic(a, c, b, e)) else 1
check(bad == 0, "held line end, any e: an extremum inside every one of %d cubics with c <= a or c >= e" % checked)
pairs = [(k1, k2) for k1 in range(1, 59) for k2 in range(k1 + 1, 59)]
bad = sum(0 if not_monotone(cubic(k1, k2, 25, 59)) else 1 for k1, k2 in pairs)
check(len(pairs) == 1653 and bad == 0,
      "P052 L's serif (b = 25, e = 59): an extremum inside every one of the %d grid pairs 1 <= a < c < 59" % len(pairs))

sys.exit(1 if failures else 0)
