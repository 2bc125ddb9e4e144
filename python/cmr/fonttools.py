"""cmr.fonttools: fontTools glyphs judged as ``cmr report FONT`` judges them.

    from fontTools.ttLib import TTFont
    import cmr.fonttools
    glyphs = TTFont("DejaVuSans.ttf").getGlyphSet()
    cmr.fonttools.check_glyph(glyphs, "O", require="curvature-extrema-at-nodes")
"""

from . import JudgeQueue, judge
from ._cmr import InputError
from .pen import SplinePen

__all__ = ["glyph_contours", "glyph_splines", "check_glyph", "check_glyphs", "font_degree"]


def font_degree(glyph_set):
    """2 for a TrueType (glyf) glyph set, 3 for a CFF one, None when the
    glyph set does not say (the pen then takes it from the curves)."""
    if hasattr(glyph_set, "glyfTable"):
        return 2
    if hasattr(glyph_set, "charStrings"):
        return 3
    return None


def glyph_contours(glyph_set, name, degree=None):
    """The glyph's contours through cmr.pen.SplinePen, as cmr.Spline objects."""
    if name not in glyph_set:
        raise InputError(f"{name}: no such glyph in the glyph set")
    pen = SplinePen(name, degree=degree or font_degree(glyph_set), glyph_set=glyph_set)
    glyph_set[name].draw(pen)
    return pen.contours


def glyph_splines(glyph_set, name, degree=None):
    """The glyph's contours through cmr.pen.SplinePen, as spline dicts (the
    files of ``cmr import``)."""
    return [s.to_dict() for s in glyph_contours(glyph_set, name, degree)]


def check_glyph(glyph_set, name, require="cmrwi", **options):
    """Each contour of glyph `name` judged with ``--require`` `require` (the
    report's gates: cmrwi, cmr, curvature-extrema-at-nodes, g2-at-smooth-nodes, ...;
    options as cmr.judge). Returns one dict per contour: "contour" (its
    name, "O/c0"), "status" ("pass" or "fail"), "findings" (one per gate
    violation: "gate", "message", "segment" or "joint", "t", with the point
    names of the contour where they say which), "spline" (the spline dict)
    and "report" (its entry of report.json)."""
    out = []
    for s in glyph_contours(glyph_set, name):
        d = s.to_dict()
        entry = judge(s, require=require, **options)
        findings = []
        for gate in entry.get("gates", []):
            for v in gate.get("violations", []):
                findings.append(dict(v, gate=gate.get("gate")))
        out.append({"contour": d["name"], "status": entry.get("status"), "findings": findings, "spline": d,
                    "report": entry})
    return out


def check_glyphs(glyph_set, names, require="cmrwi", *, depth=None, threads=0):
    """Every contour of the glyphs `names` judged with ``--require``
    `require`, as judge_many judges them, for a whole font at once: each
    glyph is drawn through the pen and handed to a cmr.JudgeQueue, so the
    judging of the glyphs drawn so far runs while the next ones are drawn.
    Returns one dict per contour, in order: "contour" (its name, "O/c0"),
    "status" and "gates" (report.json's gates, with each violation)."""
    options = {"require": require, "threads": threads}
    if depth is not None:
        options["depth"] = depth
    queue = JudgeQueue(**options)
    batch = []
    for name in names:
        batch.extend(glyph_contours(glyph_set, name))
        if len(batch) >= 256:
            queue.submit(batch)
            batch = []
    if batch:
        queue.submit(batch)
    out = []
    for entry in queue.results():
        entry["contour"] = entry.pop("name")
        out.append(entry)
    return out
