#!/usr/bin/env python3
"""Exact reference values for the space curve polynomials in Bernstein form.

Independent of the C++ code (bezierize/space_lambda.hpp): works in the
monomial basis with Python's fractions on seeded Bezier curves of degree 2..7
in R^3, forms c = P' x P'', |c|^2, g = |P'|^2,
lambda3 = (|c|^2)' g - 3 |c|^2 g', N = det(P', P'', P''') and
T = N' |c|^2 - N (|c|^2)' directly from the derivatives, checks that their
degrees are exactly 4n-8, 6n-11, 3n-9 and 7n-18 (at most, and exactly where
the seeded curve is generic), and converts to Bernstein coefficients with
b_k = sum_{i<=k} C(k,i)/C(N,i) a_i. Prints a C++ header; the test
`space_reference_current` checks that the committed header is this script's
output.

Rational space curves (seeded, degree 2..7, positive weights): from the
homogeneous polynomials X (three) and W it forms the Cartesian derivatives by
the quotient rule only, C' = h / W^2 with h = X' W - X W',
C'' = u / W^3 with u = h' W - 2 h W', C''' = v / W^4 with v = u' W - 3 u W',
and divides out the powers of W exactly (the remainders are asserted zero):
e = (h x u) / W^2 (C' x C'' = e / W^3), E = |e|^2, G = |h|^2; kappa^2 =
E W^6 / G^3, and lambda3r is the numerator of its derivative,
(A' B - A B') / (W^5 G^2) with A = E W^6, B = G^3; Nr = det(h, u, v) / W^5
(tau = W^2 Nr / E) and Tr = (A' B - A B') / W with A = W^2 Nr, B = E. It
checks the degrees 3n-6, 6n-12, 4n-4, 11n-18, 4n-12 and 11n-26 of
bezierize/space_lambda.hpp (exact for these generic curves).
"""
import random
from fractions import Fraction as F
from math import comb


def seeded_curves():
    rng = random.Random(25)
    curves = []
    for n in range(2, 8):
        for v in range(2):
            # Quarter-integers: exact in double, so the C++ input is exact.
            pts = [tuple(F(rng.randint(-16, 16), 4) for _ in range(3)) for _ in range(n + 1)]
            curves.append(("deg%d_%s" % (n, "ab"[v]), pts))
    # A planar cubic tilted out of the coordinate planes: N == 0, tau == 0.
    curves.append(("planar_cubic", [(F(0), F(0), F(0)), (F(1), F(1), F(1)), (F(3), F(2), F(2)), (F(4), F(0), F(0))]))
    return curves


def monomial(values):
    n = len(values) - 1
    a = [F(0)] * (n + 1)
    for i, p in enumerate(values):
        for j in range(n - i + 1):
            a[i + j] += comb(n, i) * comb(n - i, j) * (-1) ** j * F(p)
    return a


def deriv(a):
    return [k * a[k] for k in range(1, len(a))] or [F(0)]


def mul(a, b):
    c = [F(0)] * (len(a) + len(b) - 1)
    for i, x in enumerate(a):
        for j, y in enumerate(b):
            c[i + j] += x * y
    return c


def add(*terms):
    n = max(len(t) for _, t in terms)
    out = [F(0)] * n
    for s, t in terms:
        for i, x in enumerate(t):
            out[i] += s * x
    return out


def degree(a):
    d = len(a) - 1
    while d >= 0 and a[d] == 0:
        d -= 1
    return d  # -1 for the zero polynomial


def to_bernstein(a, N):
    assert degree(a) <= N, "degree %d exceeds %d" % (degree(a), N)
    a = (a + [F(0)] * (N + 1))[: N + 1]
    return [sum(F(comb(k, i), comb(N, i)) * a[i] for i in range(k + 1)) for k in range(N + 1)]


def curve_values(pts):
    n = len(pts) - 1
    X = [monomial([p[k] for p in pts]) for k in range(3)]
    d1 = [deriv(x) for x in X]
    d2 = [deriv(x) for x in d1]
    d3 = [deriv(x) for x in d2]
    c = [add((1, mul(d1[1], d2[2])), (-1, mul(d1[2], d2[1]))),
         add((1, mul(d1[2], d2[0])), (-1, mul(d1[0], d2[2]))),
         add((1, mul(d1[0], d2[1])), (-1, mul(d1[1], d2[0])))]
    c2 = add(*[(1, mul(ck, ck)) for ck in c])
    g = add(*[(1, mul(x, x)) for x in d1])
    lam = add((1, mul(deriv(c2), g)), (-3, mul(c2, deriv(g))))
    N = add(*[(1, mul(c[k], d3[k])) for k in range(3)])
    T = add((1, mul(deriv(N), c2)), (-1, mul(N, deriv(c2))))
    assert degree(c2) == 4 * n - 8, (n, degree(c2))
    assert degree(lam) == 6 * n - 11, (n, degree(lam))
    out = {"c2": to_bernstein(c2, 4 * n - 8), "lambda3": to_bernstein(lam, 6 * n - 11)}
    if n >= 3 and degree(N) >= 0:
        assert degree(N) == 3 * n - 9, (n, degree(N))
        assert degree(T) == 7 * n - 18, (n, degree(T))
        out["N"] = to_bernstein(N, 3 * n - 9)
        out["T"] = to_bernstein(T, 7 * n - 18)
    else:
        assert degree(N) == -1 and degree(T) == -1
        out["N"] = []  # identically zero: a planar curve (or n = 2)
        out["T"] = []
    return out


def seeded_rational_curves():
    rng = random.Random(2025)
    curves = []
    for n in range(2, 8):
        for v in range(2):
            pts = [tuple(F(rng.randint(-16, 16), 4) for _ in range(3)) for _ in range(n + 1)]
            ws = [F(rng.randint(1, 16), 4) for _ in range(n + 1)]
            curves.append(("rdeg%d_%s" % (n, "ab"[v]), pts, ws))
    # A planar rational cubic (z = 0): Nr == 0.
    curves.append(("rplanar_cubic", [(F(0), F(0), F(0)), (F(1), F(2), F(0)), (F(3), F(2), F(0)), (F(4), F(0), F(0))],
                   [F(1), F(3), F(1, 2), F(2)]))
    return curves


def divide(a, b):
    """a / b for polynomials (monomial basis); asserts the division is exact."""
    a = list(a)
    db = degree(b)
    assert db >= 0
    if degree(a) < 0:
        return [F(0)]
    q = [F(0)] * (degree(a) - db + 1)
    for k in range(degree(a) - db, -1, -1):
        c = a[k + db] / b[db]
        q[k] = c
        for i in range(db + 1):
            a[k + i] -= c * b[i]
    assert degree(a) < 0, "inexact division"
    return q


def cross(a, b):
    return [add((1, mul(a[1], b[2])), (-1, mul(a[2], b[1]))),
            add((1, mul(a[2], b[0])), (-1, mul(a[0], b[2]))),
            add((1, mul(a[0], b[1])), (-1, mul(a[1], b[0])))]


def power(p, k):
    out = [F(1)]
    for _ in range(k):
        out = mul(out, p)
    return out


def rational_values(pts, ws):
    n = len(pts) - 1
    X = [monomial([p[k] * w for p, w in zip(pts, ws)]) for k in range(3)]
    W = monomial(ws)
    W1 = deriv(W)
    h = [add((1, mul(deriv(x), W)), (-1, mul(x, W1))) for x in X]
    u = [add((1, mul(deriv(hk), W)), (-2, mul(hk, W1))) for hk in h]
    v = [add((1, mul(deriv(uk), W)), (-3, mul(uk, W1))) for uk in u]
    e = [divide(x, power(W, 2)) for x in cross(h, u)]
    E = add(*[(1, mul(x, x)) for x in e])
    G = add(*[(1, mul(x, x)) for x in h])
    A, B = mul(E, power(W, 6)), power(G, 3)
    lam = divide(add((1, mul(deriv(A), B)), (-1, mul(A, deriv(B)))), mul(power(W, 5), power(G, 2)))
    det3 = add(*[(1, mul(c, vk)) for c, vk in zip(cross(h, u), v)])
    Nr = divide(det3, power(W, 5))
    A, B = mul(power(W, 2), Nr), E
    Tr = divide(add((1, mul(deriv(A), B)), (-1, mul(A, deriv(B)))), W)
    assert max(degree(x) for x in e) == 3 * n - 6, (n, [degree(x) for x in e])
    assert degree(E) == 6 * n - 12, (n, degree(E))
    assert degree(G) == 4 * n - 4, (n, degree(G))
    assert degree(lam) == 11 * n - 18, (n, degree(lam))
    out = {"E": to_bernstein(E, 6 * n - 12), "G": to_bernstein(G, 4 * n - 4), "lambda3": to_bernstein(lam, 11 * n - 18)}
    if n >= 3 and degree(Nr) >= 0:
        assert degree(Nr) == 4 * n - 12, (n, degree(Nr))
        assert degree(Tr) == 11 * n - 26, (n, degree(Tr))
        out["N"] = to_bernstein(Nr, 4 * n - 12)
        out["T"] = to_bernstein(Tr, 11 * n - 26)
    else:
        assert degree(Nr) == -1 and degree(Tr) == -1
        out["N"] = []
        out["T"] = []
    return out


def cpp_list(values):
    return "{" + ", ".join('"%s"' % v for v in values) + "}"


def main():
    out = ["// Generated by tests/bezierize/gen_space_reference.py; do not edit.",
           "#pragma once", "#include <array>", "#include <string>", "#include <vector>", "",
           "namespace cmr::reference {", "", "struct SpaceReference {",
           "  const char* name;", "  std::vector<std::array<double, 3>> points;",
           "  std::vector<std::string> c2;       // |P' x P''|^2, exact rationals",
           "  std::vector<std::string> lambda3;  // (|c|^2)' g - 3 |c|^2 g'",
           "  std::vector<std::string> N;        // det(P', P'', P'''); empty when identically 0",
           "  std::vector<std::string> T;        // N' |c|^2 - N (|c|^2)'; empty when identically 0",
           "};", "",
           "inline const std::vector<SpaceReference>& space_references() {",
           "  static const std::vector<SpaceReference> refs = {"]
    for name, pts in seeded_curves():
        v = curve_values(pts)
        p = "{" + ", ".join("{%r, %r, %r}" % tuple(float(x) for x in q) for q in pts) + "}"
        out.append('      {"%s", %s,' % (name, p))
        out.append("       %s," % cpp_list(v["c2"]))
        out.append("       %s," % cpp_list(v["lambda3"]))
        out.append("       %s," % cpp_list(v["N"]))
        out.append("       %s}," % cpp_list(v["T"]))
    out += ["  };", "  return refs;", "}", "",
            "struct RationalSpaceReference {",
            "  const char* name;",
            "  std::vector<std::array<double, 3>> points;",
            "  std::vector<double> weights;",
            "  std::vector<std::string> E;        // |e|^2, e = W (X' x X'') - W' (X x X'') + W'' (X x X')",
            "  std::vector<std::string> G;        // |h|^2, h = W X' - W' X",
            "  std::vector<std::string> lambda3;  // (E' W + 6 E W') G - 3 E W G'",
            "  std::vector<std::string> N;        // -det(H, H', H'', H'''); empty when identically 0",
            "  std::vector<std::string> T;        // (2 W' N + W N') E - W N E'; empty when identically 0",
            "};", "",
            "inline const std::vector<RationalSpaceReference>& rational_space_references() {",
            "  static const std::vector<RationalSpaceReference> refs = {"]
    for name, pts, ws in seeded_rational_curves():
        v = rational_values(pts, ws)
        p = "{" + ", ".join("{%r, %r, %r}" % tuple(float(x) for x in q) for q in pts) + "}"
        out.append('      {"%s", %s,' % (name, p))
        out.append("       {%s}," % ", ".join(repr(float(w)) for w in ws))
        for key in ("E", "G", "lambda3", "N"):
            out.append("       %s," % cpp_list(v[key]))
        out.append("       %s}," % cpp_list(v["T"]))
    out += ["  };", "  return refs;", "}", "", "}  // namespace cmr::reference", ""]
    print("\n".join(out), end="")


if __name__ == "__main__":
    main()
