#!/usr/bin/python3
"""Exact reference values for g3-at-smooth-nodes (report/g3.hpp).

Independent of the C++ code: a uniform cubic B-spline's pieces are put into
Bezier form by the uniform matrix ((Q0 + 4 Q1 + Q2)/6, ...), a Bezier chain's
pieces are its points; a rational piece is split into its homogeneous
coordinates. Each coordinate polynomial is written in the monomial basis
around the joint (u = 0 of the right piece, u = 1 of the left piece, by
substituting u = 1 + v), and the Cartesian Taylor coefficients of P = X / W
there come from power-series division in Python's fractions; P^(k) = k! p_k.
Then, exactly:
  planar  dkappa/ds = (det(P', P''') |P'|^2 - 3 det(P', P'') (P'.P'')) / |P'|^6
  space   dkappa/ds = sign(M) sqrt(M^2 / (|c|^2 |P'|^12)),
          M = (c.c') |P'|^2 - 3 |c|^2 (P'.P''), c = P' x P'', c' = P' x P'''
          tau = det(P', P'', P''') / |c|^2
  kappa = |c| / |P'|^3 (signed det in 2D)
and the gate's verdict at tol = 0.05 with the floors of report/g3.hpp.
Prints a C++ header; the test `g3_reference_current` checks that the
committed header is this script's output.
"""
from fractions import Fraction as F
from math import comb, sqrt, factorial

TOL = F(5, 100)


def split_half(pts):
    """de Casteljau at 1/2: the two halves (exact)."""
    levels = [pts]
    while len(levels[-1]) > 1:
        p = levels[-1]
        levels.append([tuple((a + b) / 2 for a, b in zip(p[i], p[i + 1])) for i in range(len(p) - 1)])
    return [l[0] for l in levels], [l[-1] for l in reversed(levels)]


def uniform_cubic_pieces(q):
    """Bezier points of each span of the uniform cubic B-spline on control points q."""
    out = []
    for i in range(len(q) - 3):
        a, b, c, d = q[i:i + 4]
        comb4 = lambda wa, wb, wc, wd, s: tuple((wa * x + wb * y + wc * z + wd * t) / s for x, y, z, t in zip(a, b, c, d))
        out.append([comb4(1, 4, 1, 0, 6), comb4(0, 4, 2, 0, 6), comb4(0, 2, 4, 0, 6), comb4(0, 1, 4, 1, 6)])
    return out


def monomial(coeffs_bernstein):
    """Bernstein coefficients on [0, 1] -> monomial coefficients a_j (sum a_j u^j)."""
    n = len(coeffs_bernstein) - 1
    a = [F(0)] * (n + 1)
    for k, b in enumerate(coeffs_bernstein):
        # B_k^n(u) = C(n,k) u^k (1-u)^(n-k) = sum_j C(n,k) C(n-k, j-k) (-1)^(j-k) u^j
        for j in range(k, n + 1):
            a[j] += b * comb(n, k) * comb(n - k, j - k) * (-1) ** (j - k)
    return a


def shift_to_one(a):
    """sum a_j u^j with u = 1 + v: the coefficients in v."""
    n = len(a) - 1
    return [sum(a[j] * comb(j, i) for j in range(i, n + 1)) for i in range(n + 1)]


def divide(x, w, terms=4):
    """Power series x / w (w[0] != 0), first `terms` coefficients."""
    x = x + [F(0)] * terms
    w = w + [F(0)] * terms
    q = []
    for k in range(terms):
        q.append((x[k] - sum(q[i] * w[k - i] for i in range(k))) / w[0])
    return q


def end_derivatives(hpts, at_end):
    """P', P'', P''' at u = 0 (at_end False) or u = 1 of the piece with homogeneous points hpts."""
    dim = len(hpts[0]) - 1
    series = []
    W = monomial([h[-1] for h in hpts])
    if at_end:
        W = shift_to_one(W)
    for c in range(dim):
        X = monomial([h[c] for h in hpts])
        if at_end:
            X = shift_to_one(X)
        series.append(divide(X, W))
    return [[series[c][k] * factorial(k) for c in range(dim)] for k in (1, 2, 3)]


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def measures(hpts, at_end):
    """(kappa, dkappa/ds, tau) at the end as floats; tau None in 2D."""
    d1, d2, d3 = end_derivatives(hpts, at_end)
    g = dot(d1, d1)
    if len(d1) == 2:
        c = d1[0] * d2[1] - d1[1] * d2[0]
        c1 = d1[0] * d3[1] - d1[1] * d3[0]
        kappa = float(c) / sqrt(float(g)) ** 3
        return kappa, (c1 * g - 3 * c * dot(d1, d2)) / g ** 3, None
    c, c1 = cross(d1, d2), cross(d1, d3)
    c2 = dot(c, c)
    m = dot(c, c1) * g - 3 * c2 * dot(d1, d2)
    square = m * m / (c2 * g ** 6)
    slope = (1 if m > 0 else -1 if m < 0 else 0) * sqrt(float(square))
    kappa = sqrt(float(c2 / g ** 3))
    tau = dot(cross(d1, d2), d3) / c2
    return kappa, slope, tau


def agree(a, b, floor):
    a, b = F(a), F(b)
    return abs(a - b) <= TOL * max(abs(a), abs(b), F(floor))


def homogeneous(pts, weights):
    if weights is None:
        return [tuple(F(x) for x in p) + (F(1),) for p in pts]
    return [tuple(F(x) * w for x in p) + (F(w),) for p, w in zip(pts, weights)]


def cartesian(hpts):
    return [tuple(h[c] / h[-1] for c in range(len(h) - 1)) for h in hpts], [h[-1] for h in hpts]


CASES = []


def chain_case(name, pieces_h, expect_note):
    """A chain of Bezier pieces (homogeneous) joined at knots 1, 2, ...: one spline of degree n."""
    n = len(pieces_h[0]) - 1
    pts, ws = cartesian(pieces_h[0])
    for p in pieces_h[1:]:
        c, w = cartesian(p)
        pts += c[1:]
        ws += w[1:]
    knots = [0] * n  # cmr's polar form: points + degree - 1 knots (no end knots)
    for j in range(1, len(pieces_h)):
        knots += [j] * n
    knots += [len(pieces_h)] * n
    CASES.append((name, n, knots, pts, ws if any(w != 1 for w in ws) else None, pieces_h))


# (a) planar uniform cubic B-spline (C2 by its knots, not G3).
Q = [(0, 0), (1, 3), (4, 4), (6, 1), (9, 2)]
UNIFORM = ("uniform_cubic", 3, list(range(7)), [tuple(F(x) for x in p) for p in Q], None,
           [homogeneous(p, None) for p in uniform_cubic_pieces([tuple(F(x) for x in p) for p in Q])])
CASES.append(UNIFORM)
# (b) a cubic Bezier split at 1/2 by de Casteljau (C-infinity at the split), and with P6 moved (G2 kept).
left, right = split_half([tuple(F(x) for x in p) for p in [(0, 0), (8, 24), (40, 32), (64, 0)]])
chain_case("split_cubic", [homogeneous(left, None), homogeneous(right, None)], "")
moved = right[:3] + [(right[3][0] + 8, right[3][1])]
chain_case("split_cubic_moved", [homogeneous(left, None), homogeneous(moved, None)], "")
# (c) a space cubic Bezier split at 1/2, and with P6 moved out of the osculating plane.
left, right = split_half([tuple(F(x) for x in p) for p in [(0, 0, 0), (8, 24, 8), (40, 32, -16), (64, 0, 24)]])
chain_case("split_space", [homogeneous(left, None), homogeneous(right, None)], "")
moved = right[:3] + [(right[3][0], right[3][1], right[3][2] + 16)]
chain_case("split_space_moved", [homogeneous(left, None), homogeneous(moved, None)], "")
# A rational quadratic (a hyperbola arc, w = 1, 3, 1) split at 1/2 homogeneously, and with the last weight changed.
h = homogeneous([(0, 0), (16, 32), (64, 0)], [1, 3, 1])
hl, hr = split_half(h)
chain_case("split_rational", [hl, hr], "")
hr2 = hr[:2] + [tuple(x * 2 for x in hr[2][:-1]) + (hr[2][-1] * 2,)]
chain_case("split_rational_moved", [hl, hr2], "")


def cpp(x):
    return repr(float(x))


print("// Generated by tests/report/gen_g3_reference.py; do not edit.")
print("#pragma once")
print("#include <array>")
print("#include <vector>")
print()
print("namespace cmr::reference {")
print()
print("struct G3Reference {")
print("  const char* name;")
print("  int dim;                                 // 2: planar, 3: space")
print("  int degree;")
print("  std::vector<double> knots;")
print("  std::vector<std::array<double, 3>> points;  // z = 0 in 2D")
print("  std::vector<double> weights;              // empty: polynomial")
print("  double kappa_left, kappa_right;           // at the joint (knot 1, or 3 of the uniform spline)")
print("  double slope_left, slope_right;           // dkappa/ds (signed in 2D)")
print("  double tau_left, tau_right;               // 0 in 2D")
print("  bool g3;                                  // the gate's verdict at tol 0.05")
print("};")
print()
print("inline const std::vector<G3Reference>& g3_references() {")
print("  static const std::vector<G3Reference> cases = {")
for name, n, knots, pts, ws, pieces in CASES:
    dim = len(pts[0])
    kl, sl, tl = measures(pieces[0], True)
    kr, sr, tr = measures(pieces[1], False)
    kmax = max(abs(kl), abs(kr))
    g3 = (abs(F(kl) - F(kr)) <= TOL * F(kmax) and agree(sl, sr, F(kmax) ** 2) and
          (tl is None or agree(tl, tr, F(kmax))))
    for p in pts:
        for x in p:
            assert float(x) == x, (name, x)  # every input is a double exactly
    ptxt = ", ".join("{" + ", ".join(cpp(x) for x in (list(p) + [0] * (3 - dim))) + "}" for p in pts)
    wtxt = ", ".join(cpp(w) for w in ws) if ws else ""
    print("      {\"%s\", %d, %d, {%s}, {%s}, {%s}, %s, %s, %s, %s, %s, %s, %s}," % (
        name, dim, n, ", ".join(cpp(k) for k in knots), ptxt, wtxt, cpp(kl), cpp(kr), cpp(sl), cpp(sr),
        cpp(tl or 0), cpp(tr or 0), "true" if g3 else "false"))
print("  };")
print("  return cases;")
print("}")
print()
print("}  // namespace cmr::reference")
