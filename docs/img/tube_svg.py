#!/usr/bin/env python3
"""Renders a region tube (OBJ from `cmr sweep`) to SVG for the README: a fixed
oblique view, triangles drawn back to front (painter's algorithm), flat
shading. The knot axis is stretched to 0.8 of the larger x/y extent so the
tube reads as a solid; the caption says so.

usage: tube_svg.py TUBE.obj OUT.svg [TITLE]
"""
import math
import sys


def main():
    src, dst = sys.argv[1], sys.argv[2]
    title = sys.argv[3] if len(sys.argv) > 3 else ""
    verts, faces = [], []
    with open(src) as f:
        for line in f:
            p = line.split()
            if not p:
                continue
            if p[0] == "v":
                verts.append(tuple(float(x) for x in p[1:4]))
            elif p[0] == "f":
                faces.append(tuple(int(x.split("/")[0]) - 1 for x in p[1:4]))
    lo = [min(v[i] for v in verts) for i in range(3)]
    hi = [max(v[i] for v in verts) for i in range(3)]
    span = max(hi[0] - lo[0], hi[1] - lo[1])
    zs = 0.8 * span / (hi[2] - lo[2] or 1)
    centre = [(lo[i] + hi[i]) / 2 for i in range(3)]
    pts = [((v[0] - centre[0]) / span, (v[1] - centre[1]) / span, (v[2] - centre[2]) * zs / span) for v in verts]
    az, el = math.radians(35), math.radians(25)
    ca, sa, ce, se = math.cos(az), math.sin(az), math.cos(el), math.sin(el)

    def view(p):
        # world: x right, y up, knot = z; the knot axis is drawn upwards.
        x, y, z = p
        u = ca * x - sa * y
        w = sa * x + ca * y  # depth before elevation
        return u, ce * z - se * w, se * z + ce * w

    vp = [view(p) for p in pts]
    light = (0.4, 0.8, -0.45)
    ln = math.sqrt(sum(c * c for c in light))
    light = tuple(c / ln for c in light)
    tris = []
    for a, b, c in faces:
        A, B, C = vp[a], vp[b], vp[c]
        e1 = [B[i] - A[i] for i in range(3)]
        e2 = [C[i] - A[i] for i in range(3)]
        n = (e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0])
        nn = math.sqrt(sum(x * x for x in n)) or 1
        shade = 0.35 + 0.65 * abs(sum(n[i] * light[i] for i in range(3)) / nn)
        depth = (A[2] + B[2] + C[2]) / 3
        tris.append((depth, A, B, C, shade, (pts[a][2] + pts[b][2] + pts[c][2]) / 3))
    tris.sort(key=lambda t: -t[0])
    S, M = 560, 40
    zmin = min(p[2] for p in pts)
    zmax = max(p[2] for p in pts) or 1
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{S + 2 * M}" height="{S + 2 * M}" '
           f'viewBox="-0.75 -0.75 1.5 1.5"><rect x="-0.75" y="-0.75" width="1.5" height="1.5" fill="white"/>']
    for _, A, B, C, shade, z in tris:
        s = (z - zmin) / ((zmax - zmin) or 1)  # knot: light red (first) to dark red (last)
        r, g, b = (1.0 - 0.35 * s) * shade, (0.45 - 0.3 * s) * shade, (0.45 - 0.3 * s) * shade
        col = "#%02x%02x%02x" % tuple(int(255 * max(0, min(1, c))) for c in (r, g, b))
        out.append(f'<polygon points="{A[0]:.4f},{-A[1]:.4f} {B[0]:.4f},{-B[1]:.4f} {C[0]:.4f},{-C[1]:.4f}" '
                   f'fill="{col}" stroke="{col}" stroke-width="0.001"/>')
    if title:
        out.append(f'<text x="-0.72" y="-0.68" font-family="DejaVu Sans" font-size="0.04">{title}</text>')
    out.append("</svg>")
    with open(dst, "w") as f:
        f.write("\n".join(out))


if __name__ == "__main__":
    main()
