#!/usr/bin/python3
"""An exact judge of a cubic or quadratic .glif, independent of cmr (rational arithmetic).

    exact_glif_check.py GLYPH.glif [--gates extrema,g2] [--g2-tol 0.05]

Prints one line per violation and exits 1 when there is one, else 0.

 * curvature extrema at nodes: inside no segment does the curvature
   derivative's numerator
       lambda(t) = det(P', P''') (P'.P') - 3 det(P', P'') (P'.P'')
   (degree 4n - 7 = 5 for a cubic) change sign: its Bernstein coefficients
   on [0, 1] (exact, from the power basis) are all >= 0 or all <= 0, else
   the interval is halved (de Casteljau, exact) down to depth 12 and every
   piece must be of one sign class, the same for all. A piece still mixed at
   the depth limit counts as a violation (not certified).
 * G2 at smooth nodes (tolerance 0.05 by default): at a node whose two
   tangents are exactly parallel and point the same way, the curvatures
   k = det(P', P'') / |P'|^3 on both sides satisfy
   |kl - kr| <= tol * max(|kl|, |kr|), decided exactly on k^2 (rational).

`line`, `curve` and `qcurve` contours are read; a contour is closed (no
`move`). A `qcurve` with k off-curve points is k quadratics joined at the
implied on-curve midpoints (TrueType's rule), each raised exactly to a cubic
(P0, P0 + 2/3 (P1 - P0), P2 + 2/3 (P1 - P2), P2: the same curve, the same
parametrisation, so the same curvature and lambda); an implied midpoint is a
node whose tangents are exactly parallel, so G2 is judged there too.
"""
import sys
import xml.etree.ElementTree as ET
from fractions import Fraction as F
from math import comb

DEPTH = 12


def contours(path):
    root = ET.parse(path).getroot()
    for c in root.iter("contour"):
        pts = [(F(p.get("x")), F(p.get("y")), p.get("type")) for p in c.iter("point")]
        # rotate to start at an on-curve point
        k = next(i for i, p in enumerate(pts) if p[2] in ("curve", "line", "qcurve"))
        pts = pts[k:] + pts[:k]
        segs = []
        n = len(pts)
        i = 0
        while i < n:
            start = pts[i]
            j = i + 1
            offs = []
            while pts[j % n][2] is None or pts[j % n][2] == "offcurve":
                offs.append(pts[j % n])
                j += 1
            end = pts[j % n]
            ctrl = [start] + offs + [end]
            if end[2] == "qcurve" and offs:
                on = [start]
                for a, b in zip(offs, offs[1:]):  # the implied on-curve midpoints
                    on.append(((a[0] + b[0]) / 2, (a[1] + b[1]) / 2, "qcurve"))
                on.append(end)
                for q0, q1, q2 in zip(on, offs, on[1:]):
                    segs.append([(q0[0], q0[1]), (q0[0] + 2 * (q1[0] - q0[0]) / 3, q0[1] + 2 * (q1[1] - q0[1]) / 3),
                                 (q2[0] + 2 * (q1[0] - q2[0]) / 3, q2[1] + 2 * (q1[1] - q2[1]) / 3), (q2[0], q2[1])])
                i = j
                continue
            if len(ctrl) == 2:  # a line as a cubic
                a, b = start, end
                ctrl = [a, (a[0] + (b[0] - a[0]) / 3, a[1] + (b[1] - a[1]) / 3, None),
                        (a[0] + 2 * (b[0] - a[0]) / 3, a[1] + 2 * (b[1] - a[1]) / 3, None), b]
            assert len(ctrl) == 4, "only cubic contours"
            segs.append([(p[0], p[1]) for p in ctrl])
            i = j
        yield segs


def poly_mul(a, b):
    out = [F(0)] * (len(a) + len(b) - 1)
    for i, x in enumerate(a):
        for j, y in enumerate(b):
            out[i + j] += x * y
    return out


def poly_sub(a, b):
    n = max(len(a), len(b))
    a = a + [F(0)] * (n - len(a))
    b = b + [F(0)] * (n - len(b))
    return [x - y for x, y in zip(a, b)]


def deriv(a):
    return [i * a[i] for i in range(1, len(a))] or [F(0)]


def lam(seg):
    # power basis of x(t), y(t) for the cubic Bezier
    def power(c):
        p0, p1, p2, p3 = c
        return [p0, 3 * (p1 - p0), 3 * (p2 - 2 * p1 + p0), p3 - 3 * p2 + 3 * p1 - p0]
    x = power([p[0] for p in seg])
    y = power([p[1] for p in seg])
    x1, y1 = deriv(x), deriv(y)
    x2, y2 = deriv(x1), deriv(y1)
    x3, y3 = deriv(x2), deriv(y2)
    det13 = poly_sub(poly_mul(x1, y3), poly_mul(y1, x3))
    det12 = poly_sub(poly_mul(x1, y2), poly_mul(y1, x2))
    dot11 = [a + b for a, b in zip(*[p + [F(0)] * (5 - len(p)) for p in (poly_mul(x1, x1), poly_mul(y1, y1))])]
    dot12 = [a + b for a, b in zip(*[p + [F(0)] * (5 - len(p)) for p in (poly_mul(x1, x2), poly_mul(y1, y2))])]
    return poly_sub(poly_mul(det13, dot11), [3 * c for c in poly_mul(det12, dot12)])


def bernstein(a, n):
    a = a + [F(0)] * (n + 1 - len(a))
    return [sum(F(comb(i, j), comb(n, j)) * a[j] for j in range(i + 1)) for i in range(n + 1)]


def halves(b):
    left, right, cur = [], [], list(b)
    while cur:
        left.append(cur[0])
        right.append(cur[-1])
        cur = [(cur[k] + cur[k + 1]) / 2 for k in range(len(cur) - 1)]
    return left, right[::-1]


def sign_classes(b, depth=0):
    if all(c >= 0 for c in b) and all(c <= 0 for c in b):
        return {"zero"}
    if all(c >= 0 for c in b):
        return {"pos"}
    if all(c <= 0 for c in b):
        return {"neg"}
    if b[0] * b[-1] < 0 or depth == DEPTH:
        return {"mixed"}
    l, r = halves(b)
    return sign_classes(l, depth + 1) | sign_classes(r, depth + 1)


def not_monotone(seg):
    """lambda of the cubic `seg` takes both strict signs on [0, 1] (so a root strictly inside: a curvature
    extremum): its values at the ends of de Casteljau halves (each half's first and last Bernstein
    coefficient), halving only where a half's coefficients hold both signs, down to 2^-60."""
    seen, todo = set(), [(bernstein(lam(seg), 5), 0)]
    while todo and seen != {1, -1}:
        b, depth = todo.pop()
        for v in (b[0], b[-1]):
            if v != 0:
                seen.add(1 if v > 0 else -1)
        if depth < 60 and any(c > 0 for c in b) and any(c < 0 for c in b):
            todo.extend((h, depth + 1) for h in halves(b))
    return seen == {1, -1}


def monotone(seg):
    """lambda of the cubic `seg` of one sign on [0, 1], certified by its Bernstein coefficients (subdivided)."""
    classes = sign_classes(bernstein(lam(seg), 5)) - {"zero"}
    return classes in ({"pos"}, {"neg"})


def kappa_end(seg, at_end):
    p0, p1, p2, p3 = seg
    if at_end:
        d1 = (3 * (p3[0] - p2[0]), 3 * (p3[1] - p2[1]))
        d2 = (6 * (p3[0] - 2 * p2[0] + p1[0]), 6 * (p3[1] - 2 * p2[1] + p1[1]))
    else:
        d1 = (3 * (p1[0] - p0[0]), 3 * (p1[1] - p0[1]))
        d2 = (6 * (p2[0] - 2 * p1[0] + p0[0]), 6 * (p2[1] - 2 * p1[1] + p0[1]))
    return d1, d1[0] * d2[1] - d1[1] * d2[0]


def tangent(seg, at_end):
    pts = seg[::-1] if at_end else seg
    for q in pts[1:]:
        d = (q[0] - pts[0][0], q[1] - pts[0][1])
        if d != (0, 0):
            return (-d[0], -d[1]) if at_end else d
    return (F(0), F(0))


def main():
    import argparse
    ap = argparse.ArgumentParser()
    ap.add_argument("glif")
    ap.add_argument("--gates", default="extrema,g2")
    ap.add_argument("--g2-tol", default="0.05")
    a = ap.parse_args()
    path, tol, gates = a.glif, F(a.g2_tol), a.gates.split(",")
    bad = []
    for ci, segs in enumerate(contours(path)):
        for si, seg in enumerate(segs):
            if "extrema" not in gates:
                break
            cls = sign_classes(bernstein(lam(seg), 5)) - {"zero"}
            if len(cls) > 1 or "mixed" in cls:
                bad.append(f"c{ci} segment {si}: curvature extremum inside (lambda classes {sorted(cls)})")
        for si in range(len(segs) if "g2" in gates else 0):
            a, b = segs[si - 1], segs[si]
            ta, tb = tangent(a, True), tangent(b, False)
            if ta[0] * tb[1] - ta[1] * tb[0] != 0 or ta[0] * tb[0] + ta[1] * tb[1] <= 0:
                continue  # a corner: exempt
            (va, ca), (vb, cb) = kappa_end(a, True), kappa_end(b, False)
            if ca == 0 and cb == 0:
                continue
            na, nb = va[0] ** 2 + va[1] ** 2, vb[0] ** 2 + vb[1] ** 2
            ka2, kb2 = ca * ca / na ** 3, cb * cb / nb ** 3  # kappa^2, exact
            if (ca > 0) != (cb > 0) or ca == 0 or cb == 0:
                bad.append(f"c{ci} node {si}: curvature changes sign at a smooth node")
                continue
            lo, hi = min(ka2, kb2), max(ka2, kb2)
            if lo < (1 - tol) ** 2 * hi:
                bad.append(f"c{ci} node {si}: curvature jump beyond {float(tol)}")
    for line in bad:
        print(line)
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
