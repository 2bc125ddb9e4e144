#!/usr/bin/env python3
"""The published midway-instance kink heuristic, re-implemented as the
baseline for cmr's g1-between-masters gate (issue 37, docs/interpolation.md).

What it re-implements (fontTools varLib.interpolatable's "kink" check as
described and released in 2023-2024; written anew here from that
description): for each pair of neighbouring masters, at every on-curve
node that has an off-curve neighbour,

  1. the node must look smooth at both masters: the sine of the turn from
     the incoming to the outgoing vector (node - previous point, next point
     - node) is at most T = 0.1 (about 6 degrees) and the turn is not a cusp
     (their dot product is not negative);
  2. the handle proportions r = |in| / (|in| + |out|) of the two masters
     differ by at least T (otherwise: "smooth enough");
  3. at the halfway instance (the average of the two masters' points) the
     turn's sine s_mid satisfies |s_mid| * tolerance * kinkiness > T
     (tolerance 0.95 and kinkiness 0.5 by default: |s_mid| > 0.2105);
  4. the kink is visible: its deviation |in x out| / |in + out| is at least
     upem * 0.002 * 0.5 / kinkiness font units (1 unit at 1000 upem), and at
     most T times the length |in + out|.

Only the halfway instance is looked at, and each threshold is tuned, which
is what the comparison measures. The pairs of masters: for a designspace,
the sources that differ along one axis with no source between them; for a
TrueType variable font (gvar), the default and each peak of the gvar
regions, with every other axis at its default (as fontTools does).

    /usr/bin/python3 tools/bench/midway_kinks.py FONT.designspace|VF.ttf [--glyphs A,B|all] [--json]

Prints one line per kink (glyph, contour, point in the font's own order,
the pair of masters, s_mid and the deviation) or, with --json, a JSON list;
then the count and the time it took. Nothing is asserted: a benchmark
baseline, not a test.
"""

import argparse
import json
import math
import sys
import time

T = 0.1
TOLERANCE = 0.95
KINKINESS = 0.5
KINK_LENGTH = 0.002  # of the em


def turn(prev, node, nxt):
    """(sine of the turn, dot of in and out, |in|, |out|) at `node`."""
    ix, iy = node[0] - prev[0], node[1] - prev[1]
    ox, oy = nxt[0] - node[0], nxt[1] - node[1]
    li, lo = math.hypot(ix, iy), math.hypot(ox, oy)
    if li == 0 or lo == 0:
        return None
    return (ix * oy - iy * ox) / (li * lo), ix * ox + iy * oy, li, lo


def kinks_of_contour(a, b, on_a, upem):
    """Indices (into the contour) of the nodes the heuristic flags between
    the masters' point lists a and b (same length), with s_mid, deviation."""
    out = []
    n = len(a)
    threshold = upem * KINK_LENGTH * 0.5 / KINKINESS
    for i in range(n):
        if not on_a[i]:
            continue
        p, q = (i - 1) % n, (i + 1) % n
        if on_a[p] and on_a[q]:
            continue  # two lines: no handle, no kink
        ta, tb = turn(a[p], a[i], a[q]), turn(b[p], b[i], b[q])
        if ta is None or tb is None:
            continue
        if abs(ta[0]) > T or abs(tb[0]) > T or ta[1] < 0 or tb[1] < 0:
            continue  # not smooth at a master, or a cusp
        ra, rb = ta[2] / (ta[2] + ta[3]), tb[2] / (tb[2] + tb[3])
        if abs(ra - rb) < T:
            continue  # proportions alike: taken as smooth
        mid = [((x0 + x1) / 2, (y0 + y1) / 2) for (x0, y0), (x1, y1) in ((a[p], b[p]), (a[i], b[i]), (a[q], b[q]))]
        tm = turn(*mid)
        if tm is None:
            continue
        s_mid = tm[0]
        if abs(s_mid) * TOLERANCE * KINKINESS <= T:
            continue
        ix, iy = mid[1][0] - mid[0][0], mid[1][1] - mid[0][1]
        ox, oy = mid[2][0] - mid[1][0], mid[2][1] - mid[1][1]
        chord = math.hypot(ix + ox, iy + oy)
        if chord == 0:
            continue
        deviation = abs(ix * oy - iy * ox) / chord
        if deviation < threshold or deviation / chord > T:
            continue
        out.append((i, s_mid, deviation))
    return out


# ------------------------------------------------------------ sources


def variable_font_masters(path, names):
    """(upem, [(label, location, {glyph: [(points, on_flags)]})]) of a gvar
    font: the default and each region peak of the glyphs asked for."""
    from fontTools.ttLib import TTFont

    font = TTFont(path)
    if "gvar" not in font or "fvar" not in font:
        raise SystemExit(f"midway_kinks: {path}: not a TrueType variable font (no fvar/gvar)")
    cmap = font.getBestCmap() or {}
    if names == ["all"]:
        glyphs = font.getGlyphOrder()
    else:
        glyphs = [cmap.get(ord(c), c) if len(c) == 1 else c for c in names] if names else sorted(
            {cmap[c] for c in range(0x41, 0x7B) if c in cmap and chr(c).isalpha()})
    peaks = set()
    for g in glyphs:
        for var in font["gvar"].variations.get(g, []):
            peaks.add(tuple(sorted((tag, support[1]) for tag, support in var.axes.items())))
    axes = {a.axisTag: a for a in font["fvar"].axes}

    def user(tag, v):
        a = axes[tag]
        return a.defaultValue + v * ((a.maxValue if v > 0 else a.defaultValue) - (a.defaultValue if v > 0 else a.minValue))

    def outlines(instance):
        """The glyphs of a static instance (components placed and varied,
        as FreeType loads them; fontTools' getGlyphSet(location) varies a
        composite's offsets but not its components' points)."""
        glyf = instance["glyf"]
        out = {}
        for g in glyphs:
            glyph = glyf[g]
            if glyph.numberOfContours == 0:
                continue
            coords, ends, flags = glyph.getCoordinates(glyf)
            if not len(ends):
                continue
            contours, start = [], 0
            for end in ends:
                contours.append(([tuple(coords[k]) for k in range(start, end + 1)],
                                 [bool(flags[k] & 1) for k in range(start, end + 1)]))
                start = end + 1
            out[g] = contours
        return out

    from fontTools.varLib import instancer

    if "avar" in font:
        raise SystemExit(f"midway_kinks: {path}: has avar, which this baseline's instancing does not invert")
    masters = [("default", {}, outlines(font))]
    for peak in sorted(peaks, key=lambda p: (len(p), p)):
        loc = dict(peak)
        label = ",".join(f"{tag}={user(tag, v):g}" for tag, v in peak)
        full = {tag: user(tag, loc.get(tag, 0)) for tag in axes}
        masters.append((label, loc, outlines(instancer.instantiateVariableFont(TTFont(path), full))))
    return font["head"].unitsPerEm, masters, glyphs


def designspace_masters(path, names):
    from fontTools.designspaceLib import DesignSpaceDocument
    import ufoLib2

    doc = DesignSpaceDocument.fromfile(path)
    masters, upem, glyphs = [], 1000, None
    for source in doc.sources:
        font = ufoLib2.Font.open(source.path)
        upem = font.info.unitsPerEm or upem
        chosen = sorted(font.keys()) if names in ([], ["all"]) else names
        glyphs = glyphs or chosen
        out = {}
        for g in chosen:
            if g not in font:
                continue
            out[g] = [([(p.x, p.y) for p in c.points], [p.type is not None for p in c.points]) for c in font[g].contours]
        label = ",".join(f"{k}={v:g}" for k, v in sorted(source.location.items()))
        masters.append((label, dict(source.location), out))
    return upem, masters, glyphs


def pairs(masters):
    """Neighbouring masters: differing in one axis, none between them."""
    out = []
    for i, (_, li, _) in enumerate(masters):
        for j in range(i + 1, len(masters)):
            lj = masters[j][1]
            keys = set(li) | set(lj)
            diff = [k for k in keys if li.get(k, 0) != lj.get(k, 0)]
            if len(diff) != 1:
                continue
            k = diff[0]
            lo, hi = sorted((li.get(k, 0), lj.get(k, 0)))
            between = any(all(m[1].get(x, 0) == li.get(x, 0) for x in keys if x != k) and lo < m[1].get(k, 0) < hi
                          for m in masters)
            if not between:
                out.append((i, j))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("source")
    ap.add_argument("--glyphs", default="")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    names = [g for g in args.glyphs.split(",") if g]
    t0 = time.perf_counter()
    if args.source.endswith(".designspace"):
        upem, masters, glyphs = designspace_masters(args.source, names)
    else:
        upem, masters, glyphs = variable_font_masters(args.source, names)
    found = []
    for i, j in pairs(masters):
        for g in glyphs:
            a, b = masters[i][2].get(g), masters[j][2].get(g)
            if a is None or b is None or len(a) != len(b):
                continue
            for c, ((pa, on_a), (pb, on_b)) in enumerate(zip(a, b)):
                if len(pa) != len(pb) or on_a != on_b:
                    continue
                for point, s_mid, deviation in kinks_of_contour(pa, pb, on_a, upem):
                    found.append({"glyph": g, "contour": c, "point": point, "name": f"{g}/c{c}/p{point}",
                                  "between": [masters[i][0], masters[j][0]], "sin_mid": s_mid, "deviation": deviation})
    seconds = time.perf_counter() - t0
    if args.json:
        json.dump({"kinks": found, "seconds": seconds, "pairs": [[masters[i][0], masters[j][0]] for i, j in pairs(masters)]},
                  sys.stdout, indent=1)
        print()
    else:
        for k in found:
            print(f"{k['name']}  between {k['between'][0]} and {k['between'][1]}: sin {k['sin_mid']:+.3f} at the "
                  f"halfway instance, deviation {k['deviation']:.2f} units")
        print(f"midway_kinks: {len(found)} kinks in {len(glyphs)} glyphs, {seconds:.2f} s")


if __name__ == "__main__":
    main()
