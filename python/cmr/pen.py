"""cmr.pen.SplinePen: a fontTools segment pen whose contours become cmr
splines, as ``cmr import FONT`` makes them (io/font.hpp).

    from fontTools.ttLib import TTFont
    from cmr.pen import SplinePen
    font = TTFont("DejaVuSans.ttf")
    pen = SplinePen("O")
    font.getGlyphSet()["O"].draw(pen)
    pen.splines   # one spline-file dict per contour, with "point_names"

The pen records each contour's points in drawing order with their kind
(on-curve, quadratic or cubic off-curve; TrueType's implied on-curve points
stay implied, as in the font) and hands them to the importer's own contour
builder (io/font.cpp: outline_contour, through cmr._cmr._font_contour), so knots,
inner points of lines (CFF: k = 21845/65536) and point names are those of
``cmr import``: TrueType "O/c0/p3", "O/c0/p2+p3" (an implied node or a line's
midpoint); CFF "A/c0/n0", "n0.out", "n1.in", "n0+n1@1/3".

What the pen cannot know (docs/python.md):
 * TrueType point numbers are counted from the contour's first point as
   drawn. fontTools draws a glyf contour from its first on-curve point, so
   the numbers equal the font's when the contour's first point is on-curve
   (the usual case); otherwise they are rotated (the spline and every verdict
   are the same).
 * The degree: a contour with curveTo is cubic, with qCurveTo quadratic; a
   glyph of lines only is quadratic unless `degree=3` is given (FreeType
   takes it from the font's format; cmr.fonttools.check_glyph passes it).
 * An open contour (endPath) is closed, as FreeType closes every contour.
"""

import numpy as np

from ._cmr import InputError, _font_contour

__all__ = ["SplinePen"]


class SplinePen:
    """A fontTools segment pen (moveTo, lineTo, curveTo, qCurveTo, closePath,
    endPath, addComponent) collecting one cmr spline per contour.

    glyph_name: the names' prefix (``cmr import`` uses the font's glyph name);
    degree: 2 or 3, or None to take it from the curves drawn;
    glyph_set: where addComponent finds components (they are drawn through a
    fontTools TransformPen; contours are numbered across components as
    FreeType numbers a composite glyph's).
    """

    def __init__(self, glyph_name="glyph", degree=None, glyph_set=None):
        if degree not in (None, 2, 3):
            raise InputError(f"degree: {degree!r} is not 2, 3 or None")
        self.glyph_name = glyph_name
        self.degree = degree
        self.glyph_set = glyph_set
        self._contours = []   # (points, tags) per finished contour
        self._points = None   # the contour being drawn
        self._tags = None
        self._splines = None

    # -- the segment pen protocol

    def moveTo(self, pt):
        self._finish()
        self._points, self._tags = [tuple(pt)], ["o"]

    def lineTo(self, pt):
        self._need_contour("lineTo")
        self._points.append(tuple(pt))
        self._tags.append("o")

    def curveTo(self, *points):
        self._need_contour("curveTo")
        if len(points) != 3:
            # A super-Bezier (more than two handles) has no counterpart in a font file.
            raise InputError(f"{self.glyph_name}: curveTo with {len(points)} points (a cubic piece has 3)")
        self._points.extend(tuple(p) for p in points)
        self._tags.extend(["c", "c", "o"])

    def qCurveTo(self, *points):
        if points and points[-1] is None:
            # A contour of off-curve points only: no moveTo before it.
            self._finish()
            self._points = [tuple(p) for p in points[:-1]]
            self._tags = ["q"] * (len(points) - 1)
            return
        self._need_contour("qCurveTo")
        *offs, on = points
        self._points.extend(tuple(p) for p in offs)
        self._tags.extend(["q"] * len(offs))
        self._points.append(tuple(on))
        self._tags.append("o")

    def closePath(self):
        self._finish()

    def endPath(self):
        self._finish()

    def addComponent(self, glyphName, transformation):
        if self.glyph_set is None:
            raise InputError(f"{self.glyph_name}: a component ({glyphName}) and no glyph_set to draw it from")
        from fontTools.pens.transformPen import TransformPen
        self._finish()
        self.glyph_set[glyphName].draw(TransformPen(self, transformation))

    # -- results

    @property
    def splines(self):
        """One spline-file dict per contour with a piece, in order
        (name "GLYPH/cC", "point_names")."""
        self._finish()
        if self._splines is None:
            degree = self.degree or self._inferred_degree()
            self._splines = []
            for c, (points, tags) in enumerate(self._contours):
                s = _font_contour(np.asarray(points, dtype=float).reshape(-1, 2), "".join(tags), c, degree,
                                  self.glyph_name)
                if s is not None:
                    self._splines.append(s)
        return self._splines

    # -- internals

    def _need_contour(self, what):
        if self._points is None:
            raise InputError(f"{self.glyph_name}: {what} before moveTo")

    def _finish(self):
        if self._points is None:
            return
        points, tags = self._points, self._tags
        # The font closes every contour with a line to its start, unwritten: a
        # last on-curve point on the start is the start (FreeType drops it).
        if len(points) > 1 and tags[-1] == "o" and tags[0] == "o" and points[-1] == points[0]:
            points, tags = points[:-1], tags[:-1]
        self._contours.append((points, tags))
        self._points = self._tags = None
        self._splines = None

    def _inferred_degree(self):
        tags = "".join("".join(t) for _, t in self._contours)
        return 3 if "c" in tags else 2
