#!/usr/bin/python3
"""Independent exact check of g1-between-masters (report/interpolation.hpp).

    interpolation_check.py DESIGNSPACE REPORT_JSON NODE

Reads the two masters of a two-source designspace (its .glif files and the
Weight axis's <map>, with xml.etree: nothing of cmr), takes the node NODE
(a point index of contour 0 of glyph "O"), and with fractions.Fraction:

  u(s) = (1 - s) u0 + s u1   (incoming tangent: node - the point before it)
  v(s) = (1 - s) v0 + s v1   (outgoing tangent: the point after it - node)
  c(s) = u x v = c0 + c1 s + c2 s^2     (power basis, exact)
  d(s) = u . v

If c is identically zero the node is G1 throughout and report.json must
have no g1-between-masters violation. Otherwise the roots of c in [0, 1]
(exact: a quadratic's roots by its discriminant) bound the intervals where
the node is a kink, and the worst angle lies at a root of
g = c' d - c d' (degree <= 2) in (0, 1), from the quadratic formula with a
50-digit Decimal square root. The report's message must name the same
interval in user values (s mapped to design linearly, design to user by the
map backwards), the worst s within 1e-9, the worst angle within 1e-6
degrees and the user location within 1e-6.

Prints "ok: ..." and exits 0, or a line saying what differs and exits 1.
"""
import json
import math
import os
import re
import sys
import xml.etree.ElementTree as ET
from decimal import Decimal, getcontext
from fractions import Fraction as F

getcontext().prec = 50


def points(glif):
    c = ET.parse(glif).getroot().find("outline").find("contour")
    return [(F(p.get("x")), F(p.get("y"))) for p in c.findall("point")]


def glif_of(ufo):
    import plistlib
    with open(os.path.join(ufo, "glyphs", "contents.plist"), "rb") as f:
        return os.path.join(ufo, "glyphs", plistlib.load(f)["O"])


def poly_mul(a, b):
    out = [F(0)] * (len(a) + len(b) - 1)
    for i, x in enumerate(a):
        for j, y in enumerate(b):
            out[i + j] += x * y
    return out


def poly_add(a, b, sign=1):
    n = max(len(a), len(b))
    a = a + [F(0)] * (n - len(a))
    b = b + [F(0)] * (n - len(b))
    return [x + sign * y for x, y in zip(a, b)]


def deriv(a):
    return [i * a[i] for i in range(1, len(a))] or [F(0)]


def ev(a, s):
    return sum(c * s ** i for i, c in enumerate(a))


def real_roots(a):
    """Roots of a polynomial of degree <= 2 (power basis), as Decimals (exact ones as Fractions)."""
    while len(a) > 1 and a[-1] == 0:
        a = a[:-1]
    if len(a) == 1:
        return []
    if len(a) == 2:
        return [-a[0] / a[1]]
    c, b, q = a
    disc = b * b - 4 * q * c
    if disc < 0:
        return []
    if disc == 0:
        return [-b / (2 * q)]
    r = Decimal(disc.numerator) / Decimal(disc.denominator)
    sq = r.sqrt()
    bd = Decimal(b.numerator) / Decimal(b.denominator)
    qd = Decimal(q.numerator) / Decimal(q.denominator)
    return sorted([(-bd - sq) / (2 * qd), (-bd + sq) / (2 * qd)])


def main():
    ds_path, report_path, node = sys.argv[1], sys.argv[2], int(sys.argv[3])
    ds = ET.parse(ds_path).getroot()
    axis = ds.find("axes").find("axis")
    amap = [(F(m.get("input")), F(m.get("output"))) for m in axis.findall("map")]
    srcs = ds.find("sources").findall("source")
    folder = os.path.dirname(ds_path)
    design = [F(s.find("location").find("dimension").get("xvalue")) for s in srcs]
    pts = [points(glif_of(os.path.join(folder, s.get("filename")))) for s in srcs]
    if design[0] > design[1]:
        design.reverse()
        pts.reverse()
    n = len(pts[0])
    u = [(p[node][0] - p[node - 1][0], p[node][1] - p[node - 1][1]) for p in pts]
    v = [(p[(node + 1) % n][0] - p[node][0], p[(node + 1) % n][1] - p[node][1]) for p in pts]
    # Affine in s: coefficient lists in the power basis.
    ux, uy = [u[0][0], u[1][0] - u[0][0]], [u[0][1], u[1][1] - u[0][1]]
    vx, vy = [v[0][0], v[1][0] - v[0][0]], [v[0][1], v[1][1] - v[0][1]]
    c = poly_add(poly_mul(ux, vy), poly_mul(uy, vx), -1)
    d = poly_add(poly_mul(ux, vx), poly_mul(uy, vy))

    def user(s):
        dz = design[0] + (design[1] - design[0]) * s
        for (u0, d0), (u1, d1) in zip(amap, amap[1:]):
            if d0 <= dz <= d1:
                return u0 + (dz - d0) * (u1 - u0) / (d1 - d0)
        return dz

    with open(report_path) as f:
        report = json.load(f)
    msgs = [v["message"] for s in report["splines"] for g in s.get("gates", [])
            if g["gate"] == "g1-between-masters" for v in g["violations"]]
    if all(x == 0 for x in c):
        if any(x <= 0 for x in (ev(d, F(0)), ev(d, F(1)))) or real_roots(d) and any(0 < r < 1 for r in real_roots(d)):
            print("FAIL: fixture: the tangents reverse; not a test of the G1 case")
            return 1
        if msgs:
            print("FAIL: c(s) == 0 (G1 at every s) but cmr reports: " + msgs[0])
            return 1
        print("ok: c(s) is identically 0; cmr reports no violation")
        return 0
    if ev(c, F(0)) != 0 or ev(c, F(1)) != 0:
        print("FAIL: fixture: the node is not collinear at both masters")
        return 1
    roots = [r for r in real_roots(c) if 0 <= r <= 1]
    # c(0) = c(1) = 0, c != 0 of degree 2: exactly the roots 0 and 1, kink on (0, 1).
    if [F(r) if isinstance(r, F) else r for r in roots] != [0, 1]:
        print("FAIL: unexpected roots of c: %s" % roots)
        return 1
    g = poly_add(poly_mul(deriv(c), d), poly_mul(c, deriv(d)), -1)
    crit = [r for r in real_roots(g[:3] if all(x == 0 for x in g[3:]) else g) if 0 < r < 1]
    if len(g) > 3 and any(x != 0 for x in g[3:]):
        print("FAIL: g has degree > 2: %s" % g)
        return 1

    def angle(s):
        s = F(s) if not isinstance(s, Decimal) else F(str(s))
        return abs(math.degrees(math.atan2(float(ev(c, s)), float(ev(d, s)))))

    worst = max(crit, key=angle)
    ws = float(worst)
    if len(msgs) != 1:
        print("FAIL: expected one g1-between-masters violation, cmr reports %d" % len(msgs))
        return 1
    m = msgs[0]
    num = r"(-?[0-9.eE+-]+)"
    rng = re.search(r"Weight in \(" + num + ", " + num + r"\)", m)
    wa = re.search(r"worst " + num + r" degrees at \{\"Weight\": " + num + r"\} \(s = " + num + r"\)", m)
    if not rng or not wa:
        print("FAIL: message not understood: " + m)
        return 1
    lo, hi = float(user(F(0))), float(user(F(1)))
    checks = [
        (abs(float(rng.group(1)) - lo) < 1e-9 and abs(float(rng.group(2)) - hi) < 1e-9,
         "interval (%g, %g), expected (%g, %g)" % (float(rng.group(1)), float(rng.group(2)), lo, hi)),
        (abs(float(wa.group(3)) - ws) < 1e-9, "worst s %s, expected %.15g" % (wa.group(3), ws)),
        (abs(float(wa.group(1)) - angle(worst)) < 1e-3, "worst angle %s, expected %.6f" % (wa.group(1), angle(worst))),
        (abs(float(wa.group(2)) - float(user(F(str(worst))))) < 1e-3,
         "worst Weight %s, expected %.6f" % (wa.group(2), float(user(F(str(worst)))))),
        (lo < float(wa.group(2)) < hi, "the worst Weight is not strictly between the masters"),
    ]
    for ok, what in checks:
        if not ok:
            print("FAIL: " + what + " (" + m + ")")
            return 1
    print("ok: c(s) = %s (power basis), kink for Weight in (%g, %g); worst %.4f degrees at s = %.12f, Weight %.6f"
          % ([str(x) for x in c], lo, hi, angle(worst), ws, float(user(F(str(worst))))))
    return 0


if __name__ == "__main__":
    sys.exit(main())
