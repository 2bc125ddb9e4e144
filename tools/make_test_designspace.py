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
NODES = {"kink": (REGULAR, BOLD_KINK), "proportional": (REGULAR, BOLD_PROPORTIONAL)}
# The Weight axis: user values and their design values.
USER = (400, 700)
DESIGN = (40, 120)


def glyph_o(font, m, extra=False):
    g = font.newGlyph("O")
    g.unicodes = [ord("O")]
    g.width = 600
    pen = g.getPointPen()
    pen.beginPath()
    pen.addPoint((0, 0), segmentType="curve", smooth=True)
    pen.addPoint(m["v"])
    pen.addPoint(m["h"])
    pen.addPoint(m["b"], segmentType="curve")
    if extra:
        pen.addPoint((m["k"][0] // 2, m["b"][1]), segmentType="line")
    pen.addPoint(m["k"])
    pen.addPoint((-m["u"][0], -m["u"][1]))
    pen.endPath()


def ufo(path, style, m, extra=False):
    f = ufoLib2.Font()
    f.info.familyName = "Interp Test"
    f.info.styleName = style
    f.info.unitsPerEm = 1000
    glyph_o(f, m, extra)
    f.save(path, overwrite=True)


def designspace(out, name, bold_ufo, default=400, bold_file=None):
    doc = DesignSpaceDocument()
    a = AxisDescriptor()
    a.name, a.tag, a.minimum, a.default, a.maximum = "Weight", "wght", USER[0], default, USER[1]
    a.map = list(zip(USER, DESIGN))
    doc.addAxis(a)
    for file, style, w in (("Regular.ufo", "Regular", DESIGN[0]), (bold_file or bold_ufo, "Bold", DESIGN[1])):
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


if __name__ == "__main__":
    main()
