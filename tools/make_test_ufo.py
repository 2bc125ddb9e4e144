#!/usr/bin/python3
"""Test fixture: a UFO 3 source made from a binary font's glyphs.

    make_test_ufo.py FONT OUT.ufo [GLYPHS]

GLYPHS is a string of characters (default A-Z a-z). Each glyph's outline is
drawn through fontTools' point pen into a ufoLib2 font (Debian
python3-fonttools, python3-ufolib2), so a TrueType font gives qcurve
contours and a CFF font curve contours, with the font's unitsPerEm,
family and style, as a designer's source would have them. Used by the tests
of cmr's source input (tests/report/ufo_fix_test.py).
"""
import sys

import ufoLib2
from fontTools.pens.pointPen import SegmentToPointPen
from fontTools.ttLib import TTFont


def main():
    font_path, out = sys.argv[1], sys.argv[2]
    chars = sys.argv[3] if len(sys.argv) > 3 else "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
    tt = TTFont(font_path)
    cmap = tt.getBestCmap()
    glyph_set = tt.getGlyphSet()
    ufo = ufoLib2.Font()
    ufo.info.unitsPerEm = tt["head"].unitsPerEm
    names = tt["name"]
    ufo.info.familyName = names.getDebugName(1) or "Test"
    ufo.info.styleName = names.getDebugName(2) or "Regular"
    for ch in chars:
        name = cmap.get(ord(ch))
        if name is None:
            continue
        g = ufo.newGlyph(name)
        g.unicodes = [ord(ch)]
        g.width = glyph_set[name].width
        glyph_set[name].draw(SegmentToPointPen(g.getPointPen()))
    ufo.save(out, overwrite=True)


if __name__ == "__main__":
    main()
