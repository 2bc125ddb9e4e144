#!/usr/bin/python3
"""Test fixture: small two-master designspaces for the interpolation gates.

    make_test_designspace.py OUT_DIR

Writes into OUT_DIR (Debian python3-ufolib2 and python3-fonttools'
designspaceLib, as a designer's tools would):

  kink.designspace          Regular (Weight 400) and Bold (Weight 700), glyph
                            "O": one contour whose node p0 is smooth="yes" and
                            G1 at both masters, its handles' lengths in ratio
                            2 (Regular) and 4 (Bold): a kink at every weight
                            strictly between.
  proportional.designspace  the same, Bold's handles in ratio 2 as well:
                            G1 at every weight.
  incompatible.designspace  Bold's "O" has one point more.
  missing.designspace       names a source UFO that does not exist.
  bad_default.designspace   an axis whose default lies outside its range.
  bump.designspace          glyph "O": one cubic piece (then two lines) whose
                            curvature increases at both masters but has an
                            interior extremum at the halfway instance
                            (bezierize/between.hpp's cubic_bump pair, times 50).
  three.designspace         kink's Regular and Bold with a Medium master at
                            Weight 550 (design 80), G1 with handles in ratio
                            3: two pieces (Regular-Medium, Medium-Bold), each
                            a kink; none from Regular straight to Bold.
  similar.designspace       the same Regular, Bold = 2 x Regular: every
                            instance is similar, curvature monotone throughout.
  rounded.designspace       p0 marked smooth but rounded to integers: 0.19
                            degrees off G1 at Regular, 0.57 at Bold, 19.4
                            degrees between (for g1-between-masters:DEG).
  zeroline.designspace      kink's "O" with a line after node b: 50 units
                            long at Regular, of zero length at Bold (its end
                            on b), as Inter's section sign at Weight 900: the
                            masters' points correspond only with that line
                            kept; p0 is still a kink between them.
  zeroline_proportional.designspace  the same with Bold's handles in
                            proportion: G1 at every weight.
  three_fixable.designspace Regular (handles 1:2), Medium (1:3, as in
                            three) and BoldProportional (1:2): a kink on both
                            pieces, fixed by moving Medium's handles alone.
  lineside.designspace      glyph "O" whose smooth node p0 has a line before
                            it (from the node L = -3u) and a handle after it:
                            line 300 : handle 200 at Regular, 90 : 120 units
                            of (2, 1) at Bold, a kink between; only the
                            handle may move (the line stays a line).
  lineside_odd.designspace  the same with Bold's line 7 units of (2, 1): no
                            handle on the integer grid in either master
                            makes the node G1 throughout.
  quadratic.designspace     kink's glyph drawn with TrueType quadratics
                            (qcurve, an implied on-curve point between each
                            two off-curve points): the same kink at p0.
  quadratic_shared.designspace  a TrueType contour whose off-curve point
                            p1 is the outgoing handle of the smooth node p0
                            and the incoming one of the smooth node p2, with
                            a line into p0 (from p5): a kink at p0 (line and
                            handle 1:2 along (1, 0) at Regular, 1:4 along
                            (2, 1) at Bold), p2 G1 throughout. Only p1 can
                            fix p0, and moving it must keep p2 G1.
  quadratic_ring.designspace  a TrueType contour of three smooth on-curve
                            points, each between two off-curve points that
                            it shares with its neighbours (a closed ring):
                            p2 is a kink (handles 1:2 at Regular, 1:1 along
                            another direction at Bold), p0 and p4 G1
                            throughout; a fix moves shared points, so all
                            three are searched together.

The Weight axis maps user 400..700 to design 40..120 (a <map>), so the
findings' user values are not the design values. NODES gives the node's
tangents; tests/report/interpolation_check.py re-derives the answer from
them with fractions.Fraction.
"""
import os
import sys

import ufoLib2
from fontTools.designspaceLib import AxisDescriptor, DesignSpaceDocument, SourceDescriptor

# Node p0 at (0, 0): incoming tangent u = p0 - (the point before it),
# outgoing v = (the point after it) - p0. Regular: u = (100, 0), v = (200, 0).
REGULAR = {"u": (100, 0), "v": (200, 0), "b": (0, 400), "h": (300, 400), "k": (-300, 400)}
BOLD_KINK = {"u": (60, 30), "v": (240, 120), "b": (0, 420), "h": (330, 420), "k": (-330, 420)}
BOLD_PROPORTIONAL = dict(BOLD_KINK, v=(120, 60))
MEDIUM = {"u": (80, 20), "v": (240, 60), "b": (0, 410), "h": (315, 410), "k": (-315, 410)}
ROUNDED_REGULAR = dict(REGULAR, u=(100, 0), v=(300, 1))
ROUNDED_BOLD = dict(BOLD_KINK, u=(100, 100), v=(50, 51))
NODES = {"kink": (REGULAR, BOLD_KINK), "proportional": (REGULAR, BOLD_PROPORTIONAL),
         "rounded": (ROUNDED_REGULAR, ROUNDED_BOLD)}
# The Weight axis: user values and their design values.
USER = (400, 700)
DESIGN = (40, 120)


def o_pen(font):
    """A new glyph "O" (width 600) of `font`, its point pen with a path begun."""
    g = font.newGlyph("O")
    g.unicodes = [ord("O")]
    g.width = 600
    pen = g.getPointPen()
    pen.beginPath()
    return pen


def glyph_o(font, m, extra=False, line=None):
    pen = o_pen(font)
    pen.addPoint((0, 0), segmentType="curve", smooth=m.get("smooth", True))
    pen.addPoint(m["v"])
    pen.addPoint(m["h"])
    pen.addPoint(m["b"], segmentType="curve")
    if line is not None:  # a line from b to b + line (zero length when line is (0, 0))
        pen.addPoint((m["b"][0] + line[0], m["b"][1] + line[1]), segmentType="line")
    if extra:
        pen.addPoint((m["k"][0] // 2, m["b"][1]), segmentType="line")
    pen.addPoint(m["k"])
    pen.addPoint((-m["u"][0], -m["u"][1]))
    pen.endPath()


def glyph_lineside(font, m, line_end, other):
    """Node p0 at (0, 0), smooth, with a line from `line_end` into it and
    the handle m["v"] out of it (then m["h"], m["b"], m["k"], `other`)."""
    pen = o_pen(font)
    pen.addPoint((0, 0), segmentType="line", smooth=True)
    pen.addPoint(m["v"])
    pen.addPoint(m["h"])
    pen.addPoint(m["b"], segmentType="curve")
    pen.addPoint(m["k"])
    pen.addPoint(other)
    pen.addPoint(line_end, segmentType="curve")
    pen.endPath()


def glyph_quadratic(font, m):
    """glyph_o's points as one TrueType contour: p0 (0, 0) an on-curve
    qcurve point, smooth, between the off-curve points -u and v; b on-curve;
    implied on-curve points halfway between v and h and between k and -u."""
    pen = o_pen(font)
    pen.addPoint((0, 0), segmentType="qcurve", smooth=True)
    pen.addPoint(m["v"])
    pen.addPoint(m["h"])
    pen.addPoint(m["b"], segmentType="qcurve")
    pen.addPoint(m["k"])
    pen.addPoint((-m["u"][0], -m["u"][1]))
    pen.endPath()


# quadratic_shared's points: p0 (0, 0) after a line from p5, the shared
# off-curve p1, p2 (on-curve, smooth), p2's outgoing handle p3, one more
# off-curve p4 (an implied on-curve point between them), p5 on-curve.
SHARED_REGULAR = [(0, 0), (200, 0), (300, 100), (350, 150), (-100, 300), (-100, 0)]
SHARED_BOLD = [(0, 0), (240, 120), (340, 220), (390, 270), (-100, 320), (-60, -30)]


def glyph_shared(font, pts):
    pen = o_pen(font)
    for k, p in enumerate(pts):
        kind = {0: "line", 2: "qcurve", 5: "qcurve"}.get(k)
        pen.addPoint(p, segmentType=kind, smooth=k in (0, 2))
    pen.endPath()


# quadratic_ring's points: on-curve p0, p2, p4 (smooth), off-curve p1, p3, p5.
RING_REGULAR = [(300, 0), (600, 0), (500, 200), (300, 600), (150, 300), (0, 0)]
RING_BOLD = [(330, 0), (660, 0), (480, 350), (300, 700), (150, 350), (0, 0)]


def glyph_ring(font, pts):
    pen = o_pen(font)
    for k, p in enumerate(pts):
        pen.addPoint(p, segmentType="qcurve" if k % 2 == 0 else None, smooth=k % 2 == 0)
    pen.endPath()


def plain_ufo(path, style, draw):
    f = ufoLib2.Font()
    f.info.familyName = "Interp Test"
    f.info.styleName = style
    f.info.unitsPerEm = 1000
    draw(f)
    f.save(path, overwrite=True)


# The bump piece at both masters (tests/bezierize/between_exact.py's cubic_bump, times 50).
BUMP_A = [(0, 0), (100, 100), (450, 300), (600, 400)]
BUMP_B = [(0, 0), (50, 100), (250, 300), (600, 400)]


def bump_ufo(path, style, pts, scale=1):
    f = ufoLib2.Font()
    f.info.familyName = "Interp Test"
    f.info.styleName = style
    f.info.unitsPerEm = 1000
    g = f.newGlyph("O")
    g.unicodes = [ord("O")]
    g.width = 700
    p = [(x * scale, y * scale) for x, y in pts]
    pen = g.getPointPen()
    pen.beginPath()
    pen.addPoint(p[0], segmentType="line")
    pen.addPoint(p[1])
    pen.addPoint(p[2])
    pen.addPoint(p[3], segmentType="curve")
    pen.addPoint((p[3][0], p[0][1]), segmentType="line")
    pen.endPath()
    f.save(path, overwrite=True)


def ufo(path, style, m, extra=False, line=None):
    f = ufoLib2.Font()
    f.info.familyName = "Interp Test"
    f.info.styleName = style
    f.info.unitsPerEm = 1000
    glyph_o(f, m, extra, line)
    f.save(path, overwrite=True)


def designspace(out, name, bold_ufo, default=400, bold_file=None, regular="Regular.ufo", medium=None):
    doc = DesignSpaceDocument()
    a = AxisDescriptor()
    a.name, a.tag, a.minimum, a.default, a.maximum = "Weight", "wght", USER[0], default, USER[1]
    a.map = list(zip(USER, DESIGN))
    doc.addAxis(a)
    masters = [(regular, "Regular", DESIGN[0]), (bold_file or bold_ufo, "Bold", DESIGN[1])]
    if medium:
        masters.insert(1, (medium, "Medium", (DESIGN[0] + DESIGN[1]) // 2))
    for file, style, w in masters:
        s = SourceDescriptor()
        s.filename, s.name, s.styleName, s.familyName = file, style, style, "Interp Test"
        s.location = {"Weight": w}
        doc.addSource(s)
    path = os.path.join(out, name + ".designspace")
    doc.write(path)


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    ufo(os.path.join(out, "Regular.ufo"), "Regular", REGULAR)
    ufo(os.path.join(out, "Bold.ufo"), "Bold", BOLD_KINK)
    ufo(os.path.join(out, "BoldProportional.ufo"), "Bold", BOLD_PROPORTIONAL)
    ufo(os.path.join(out, "BoldIncompatible.ufo"), "Bold", BOLD_KINK, extra=True)
    designspace(out, "kink", "Bold.ufo")
    designspace(out, "proportional", "BoldProportional.ufo")
    designspace(out, "incompatible", "BoldIncompatible.ufo")
    designspace(out, "missing", "Bold.ufo", bold_file="Missing.ufo")
    designspace(out, "bad_default", "Bold.ufo", default=900)
    ufo(os.path.join(out, "Medium.ufo"), "Medium", MEDIUM)
    designspace(out, "three", "Bold.ufo", medium="Medium.ufo")
    bump_ufo(os.path.join(out, "BumpRegular.ufo"), "Regular", BUMP_A)
    bump_ufo(os.path.join(out, "BumpBold.ufo"), "Bold", BUMP_B)
    bump_ufo(os.path.join(out, "SimilarBold.ufo"), "Bold", BUMP_A, scale=2)
    designspace(out, "bump", "BumpBold.ufo", regular="BumpRegular.ufo")
    designspace(out, "similar", "SimilarBold.ufo", regular="BumpRegular.ufo")
    ufo(os.path.join(out, "RoundedRegular.ufo"), "Regular", ROUNDED_REGULAR)
    ufo(os.path.join(out, "RoundedBold.ufo"), "Bold", ROUNDED_BOLD)
    designspace(out, "rounded", "RoundedBold.ufo", regular="RoundedRegular.ufo")
    ufo(os.path.join(out, "LineRegular.ufo"), "Regular", REGULAR, line=(-50, 0))
    ufo(os.path.join(out, "LineBold.ufo"), "Bold", BOLD_KINK, line=(0, 0))
    ufo(os.path.join(out, "LineBoldProportional.ufo"), "Bold", BOLD_PROPORTIONAL, line=(0, 0))
    designspace(out, "three_fixable", "BoldProportional.ufo", medium="Medium.ufo")
    designspace(out, "zeroline", "LineBold.ufo", regular="LineRegular.ufo")
    designspace(out, "zeroline_proportional", "LineBoldProportional.ufo", regular="LineRegular.ufo")
    plain_ufo(os.path.join(out, "LinesideRegular.ufo"), "Regular",
              lambda f: glyph_lineside(f, REGULAR, (-300, 0), (-300, 100)))
    plain_ufo(os.path.join(out, "LinesideBold.ufo"), "Bold",
              lambda f: glyph_lineside(f, BOLD_KINK, (-180, -90), (-300, 0)))
    plain_ufo(os.path.join(out, "LinesideOddBold.ufo"), "Bold",
              lambda f: glyph_lineside(f, BOLD_KINK, (-14, -7), (-300, 0)))
    designspace(out, "lineside", "LinesideBold.ufo", regular="LinesideRegular.ufo")
    designspace(out, "lineside_odd", "LinesideOddBold.ufo", regular="LinesideRegular.ufo")
    plain_ufo(os.path.join(out, "QuadRegular.ufo"), "Regular", lambda f: glyph_quadratic(f, REGULAR))
    plain_ufo(os.path.join(out, "QuadBold.ufo"), "Bold", lambda f: glyph_quadratic(f, BOLD_KINK))
    designspace(out, "quadratic", "QuadBold.ufo", regular="QuadRegular.ufo")
    plain_ufo(os.path.join(out, "SharedRegular.ufo"), "Regular", lambda f: glyph_shared(f, SHARED_REGULAR))
    plain_ufo(os.path.join(out, "SharedBold.ufo"), "Bold", lambda f: glyph_shared(f, SHARED_BOLD))
    designspace(out, "quadratic_shared", "SharedBold.ufo", regular="SharedRegular.ufo")
    plain_ufo(os.path.join(out, "RingRegular.ufo"), "Regular", lambda f: glyph_ring(f, RING_REGULAR))
    plain_ufo(os.path.join(out, "RingBold.ufo"), "Bold", lambda f: glyph_ring(f, RING_BOLD))
    designspace(out, "quadratic_ring", "RingBold.ufo", regular="RingRegular.ufo")


if __name__ == "__main__":
    main()
