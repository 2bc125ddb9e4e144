"""cmr: certified curvature monotonicity of B-spline curves, in Python.

The library under the ``cmr`` command (docs/python.md). Each function mirrors a
command and returns what the command prints, as Python objects:

    import cmr
    s = cmr.Spline(3, [[0, 0], [1, 2], [3, 3], [5, 2.5], [6.5, 1], [7, -1]],
                   knots=[0, 1, 2, 3, 4, 5, 6, 7])
    cmr.analyze(s)["spline"]["cmrwi"]          # == cmr analyze FILE
    labels = cmr.region(s, point=3, size=(256, 256), backend="cpu")  # == --labels

Splines are ``cmr.Spline`` objects, dicts in the spline-file format
(docs/spline-files.md) or paths to spline files; points may be NumPy arrays
(N x 2 planar, N x 3 space curves). Bad input raises ``cmr.InputError`` (a
ValueError) with the command's one-line message; environment failures (no
Vulkan device, a full disk) raise ``cmr.EnvironmentError`` (an OSError).
Long calls release the GIL; regions, fixes, reports and analyses of more
than 256 spans can be interrupted with Ctrl-C (KeyboardInterrupt): an
analysis stops, the others finish on their own thread with the result
dropped (docs/python.md, "Threads and Ctrl-C").
"""

import inspect as _inspect
import json
import os
import tempfile
import warnings
from typing import NamedTuple

from . import _options as _o
from ._cmr import EnvironmentError, InputError, Spline  # noqa: A004 (cmr.EnvironmentError is the module's own)
from . import _cmr
from . import knots  # noqa: F401  (cmr.knots.insert, ...)

__all__ = ["Spline", "InputError", "EnvironmentError", "Note", "analyze", "segments", "region", "region_result",
           "fix", "FixResult", "fix_glyph", "fix_glyphs", "kcurve", "report", "judge", "judge_many", "JudgeQueue", "knots", "DEFAULT_DEPTH",
           "GLYPH_WORK", "MAX_GLYPH_WORK"]

DEFAULT_DEPTH = _cmr.kDefaultDepth
GLYPH_WORK = _cmr.kGlyphWork          # fix_glyph's default search budget a glyph (work units)
MAX_GLYPH_WORK = _cmr.kMaxGlyphWork


class Note(UserWarning):
    """The command's "note: ..." lines on stderr (an empty region, the CPU
    fallback of backend="auto", a closed curve's judged spans)."""


def _notes(lines):
    for line in lines:
        warnings.warn(line, Note, stacklevel=3)


def analyze(spline, **options):
    """``cmr analyze FILE [options]``: the dict the command prints as JSON
    (keys "segments", "joints", "spline"; docs/analyze.md).

    Options (keywords; see the signature): depth: --depth D; split: --split S
    or [S1, S2, ...]; mode: "cmrwi" | "cmr"; segments: --segments, as A,
    (A, B) or "A..B"; each_piece: True or [S1, S2, ...] (--each-piece);
    angle_tol, curvature_tol: --angle-tol, --curvature-tol; torsion: space
    curves' --torsion.
    """
    if not options and (type(spline) is Spline or type(spline) is dict):
        return _cmr._analyze_default(spline)  # every option at its default: nothing to convert
    return _analyze(spline, **options)


def _analyze(spline, *, depth=DEFAULT_DEPTH, split=None, mode="cmrwi", segments=None, each_piece=None,
             angle_tol=1e-3, curvature_tol=1e-6, torsion=False, **unknown):
    _o.unknown("analyze", unknown, ["depth", "split", "mode", "segments", "each_piece", "angle_tol",
                                    "curvature_tol", "torsion"])
    a = _cmr._AnalyzeArgs()
    a.depth = _o.integer("depth", depth, 0, _o.MAX_DEPTH)
    a.split = _o.joints("split", split)
    a.mode = _o.choice("mode", mode, ("cmrwi", "cmr"))
    a.segments = _o.segment_range(segments)
    a.each_piece, a.each_piece_joints = _o.each_piece(each_piece)
    a.angle_tol = _o.number("angle_tol", angle_tol)
    a.curvature_tol = _o.number("curvature_tol", curvature_tol)
    if not isinstance(torsion, bool):
        raise InputError(f"torsion: expected True or False, got {torsion!r}")
    a.torsion = torsion
    return _cmr._analyze(_o.spline(spline, "analyze"), a)


analyze.__signature__ = _inspect.signature(_analyze)


def segments(spline):
    """``cmr segments FILE``: {"segments": [{"index", "interval", "points"[, "weights"]}]}."""
    return _cmr._segments(_o.spline(spline, "segments"))


def _plane(plane):
    """plane="xy" | "yz" | "zx" | (ox, oy, oz, ux, uy, uz, vx, vy, vz): the text parse_space_plane reads."""
    if plane is None:
        return ""
    if isinstance(plane, str):
        return plane
    if isinstance(plane, (list, tuple)) and len(plane) == 9:
        return ",".join(repr(_o.number(f"plane[{i}]", v)) for i, v in enumerate(plane))
    raise InputError(f"plane: expected 'xy', 'yz', 'zx' or nine numbers (origin, u, v), got {plane!r}")


def _region_args(function, spline, point, view, size, mode, split, segments, each_piece, with_, depth, backend,
                 precision, device, plane, unknown, extra):
    _o.unknown(function, unknown, ["point", "view", "size", "mode", "split", "segments", "each_piece", "with_",
                                   "depth", "backend", "precision", "device", "plane"] + extra)
    s = _o.spline(spline, function)
    a = _cmr._RegionArgs()
    if point is None:
        raise InputError(f"{function}: point is required (the control point K placed at every pixel)")
    a.point = _o.integer("point", point, 0)
    a.with_ = _o.points_list("with_", with_)
    a.mode = _o.choice("mode", mode, ("cmrwi", "cmr"))
    a.split = _o.joints("split", split)
    a.segments = _o.segment_range(segments)
    a.each_piece, a.each_piece_joints = _o.each_piece(each_piece)
    a.depth = _o.integer("depth", depth, 0, _o.MAX_DEPTH)
    a.width, a.height = _o.size(size)
    a.view = _o.view(view)
    a.backend = _o.choice("backend", backend, ("auto", "vulkan", "cpu"))
    a.precision = _o.choice("precision", precision, ("fp64", "fp32"))
    a.device = _o.text("device", device)
    a.plane = _plane(plane)
    return s, a


def region(spline, point=None, *, view=None, size=(512, 512), mode="cmrwi", split=None, segments=None,
           each_piece=None, with_=None, depth=DEFAULT_DEPTH, backend="auto", precision="fp64", device="",
           plane=None, **unknown):
    """``cmr region FILE --point K --labels OUT.pgm``: the label map as a
    numpy.uint8 array of shape (height, width), row 0 at the top, the PGM's
    bytes (0 not monotone, 1 increasing, 2 decreasing, 3 undecided; with
    split/each_piece the codes of docs/region.md). view: (x0, y0, x1, y1),
    default the region and the moved point with a margin, as the command's
    (the control polygon's box with a margin where no region shows); size:
    (width, height).
    Notes the command prints on stderr come as cmr.Note warnings. A space
    curve's point moves in a plane (plane="xy" | "yz" | "zx" | nine numbers
    origin, u, v; default: through the point, spanned by its neighbours),
    rendered on the CPU; view is then in plane coordinates.
    """
    s, a = _region_args("region", spline, point, view, size, mode, split, segments, each_piece, with_, depth,
                        backend, precision, device, plane, unknown, [])
    labels, notes = _cmr._region(s, a, False)
    _notes(notes)
    return labels


def region_result(spline, point=None, *, view=None, size=(512, 512), mode="cmrwi", split=None, segments=None,
                  each_piece=None, with_=None, depth=DEFAULT_DEPTH, backend="auto", precision="fp64", device="",
                  plane=None, depth_map=False, contours=False, **unknown):
    """region() with the rest of the command's answer, a dict:
    "labels" (as region()), "counts" (per label name), "summary" (the JSON the
    command prints, with --stats' timings), "notes" (the stderr lines); with
    depth_map=True "depth" (uint8 (h, w), the decision level per pixel); with
    contours=True "areas" (per label, and "undecided-band") and "contours"
    (per label name, a list of (n, 2) float outlines: counter-clockwise around
    regions, clockwise around holes; --contours).
    """
    s, a = _region_args("region_result", spline, point, view, size, mode, split, segments, each_piece, with_,
                        depth, backend, precision, device, plane, unknown, ["depth_map", "contours"])
    a.depth_map = bool(depth_map)
    a.contours = bool(contours)
    return _cmr._region(s, a, True)


class FixResult(NamedTuple):
    """cmr.fix's answer: the fixed spline, each moved point's move (the
    command's "moves"), the certificate (the fixed curve re-judged by
    analyze) and the whole document `cmr fix` prints."""
    spline: Spline
    moves: list
    certificate: dict
    document: dict


def fix(spline, *, require="cmr", points=None, keep="g1", segments=None, max_move=None, tolerance=1e-6,
        depth=DEFAULT_DEPTH, grid=None, plane=None, **unknown):
    """``cmr fix FILE --require R``: the nearest certified repair (docs/fix.md).

    require: "cmr", "cmrwi", "split:S[:sharpest|flattest]", "each-piece",
    "curvature-extrema-at-nodes" (alias "extrema-at-nodes"), "no-inflection", "g2-at-smooth-nodes[:tol]",
    "each-run"; points: the points that may move ([K, ...] or "P1,P3");
    keep: "g1" | "g2" | "none"; max_move: largest move (default the curve
    size); grid: the search grids' cells per side (8..512, default 32).
    A space curve (require "cmr" or "cmrwi") moves one point in a plane
    (plane= as for region; default its neighbours' plane), as `cmr fix` does.
    Raises InputError when there is no certified fix (the command's exit 2).
    """
    _o.unknown("fix", unknown, ["require", "points", "keep", "segments", "max_move", "tolerance", "depth", "grid",
                                "plane"])
    a = _cmr._FixArgs()
    a.require = _o.text("require", require)
    a.points = _o.points_list("points", points)
    a.keep = _o.choice("keep", keep, ("g1", "g2", "none"))
    a.segments = _o.segment_range(segments)
    a.max_move = 0.0 if max_move is None else _o.number("max_move", max_move, 0.0)
    a.tolerance = _o.number("tolerance", tolerance)
    a.depth = _o.integer("depth", depth, 0, _o.MAX_DEPTH)
    a.grid = 32 if grid is None else _o.integer("grid", grid, 8, 512)
    a.plane = _plane(plane)
    fixed, doc = _cmr._fix(_o.spline(spline, "fix"), a)
    return FixResult(fixed, doc["moves"], doc["certificate"], doc)


def fix_glyph(source, glyph=None, *, require="curvature-extrema-at-nodes", grid=1, max_move=None, points=None,
              depth=DEFAULT_DEPTH, in_place=False, work=GLYPH_WORK, add_nodes=False, **unknown):
    """``cmr fix FONT.ufo --glyph NAME --require GATES``: a font source's glyph
    fixed for every required check at once, on the font's grid (docs/fix.md,
    "Font sources"; docs/type-design.md).

    source: a UFO folder or one .glif (then glyph may be left out);
    require: the report's checks, "A,B" (default curvature-extrema-at-nodes);
    grid: the grid step (1: integer font units; 0: off the grid);
    max_move: largest move of a point (default the contour's size);
    points: the points that may move, by the report's names ("o/c0/p9",
    "c0/p9", "p9" or a <point>'s name attribute), a list or "a,b";
    in_place: write the moved points' x and y into the source's .glif (no
    other byte of it, and no other file, changes);
    work: the glyph's search budget in work units (``--work``; the same fix
    on any machine): a glyph that runs out of it says so, and more searches
    further;
    add_nodes: where no move fixes a contour, split its failing cubics with
    new smooth nodes on the grid and fix again (``--add-nodes``; each such
    contour's "added_nodes" say where, and its moves name the points of
    the .glif as written, with the new points in it).
    Returns the command's document: per contour its "moves" (each with
    "point", "from", "to", "distance" and "source": [contour, point] in the
    .glif's order, so that ufoLib2's ``glyph.contours[c].points[p]`` is the
    point) and "rejudged". Raises InputError where a contour has no fix.
    """
    _o.unknown("fix_glyph", unknown,
               ["require", "grid", "max_move", "points", "depth", "in_place", "work", "add_nodes"])
    source = os.fspath(source)
    glyph = "" if glyph is None else _o.text("glyph", glyph)
    if isinstance(points, str):
        points = [p.strip() for p in points.split(",")]
    points = [] if points is None else [_o.text(f"points[{i}]", p) for i, p in enumerate(points)]
    return _cmr._fix_glyph(_o.text("source", source), glyph, _o.text("require", require), _o.number("grid", grid, 0.0),
                           0.0 if max_move is None else _o.number("max_move", max_move, 0.0), points,
                           _o.integer("depth", depth, 0, _o.MAX_DEPTH), bool(in_place),
                           _o.integer("work", work, 1, MAX_GLYPH_WORK), bool(add_nodes))


def fix_glyphs(source, glyphs="all", *, require="curvature-extrema-at-nodes", grid=1, max_move=None,
               depth=DEFAULT_DEPTH, min_severity=0.5, strict=False, in_place=False, work=GLYPH_WORK, add_nodes=False,
               **unknown):
    """``cmr fix FONT.ufo --glyphs SPEC --require GATES``: every selected glyph
    of a UFO that fails, fixed on its own as fix_glyph fixes one (the same
    answers), the glyphs in parallel (docs/fix.md, "A whole font at once").

    glyphs: as the report selects them, "A-Z,a-z", "U+hex" or "all";
    min_severity: a glyph whose every finding has a certified move below
    this many font units (the report's info findings) is left as it is
    (summary "below_severity"); strict=True: every finding counts; work:
    each glyph's search budget, and add_nodes, as fix_glyph's;
    in_place: write the fixed glyphs' .glif files together (only their
    moved points' x and y). Returns the command's document: per glyph that
    failed, "glyph", "fixed", its "contours" (as fix_glyph's) and, where no
    move passes, its "reason"; and a "summary" (judged, already, fixed,
    unfixed, without_contours, missing; "below_severity" names the glyphs
    left for their info findings). A glyph without a fix does not
    raise: the others are still fixed (and written).
    """
    _o.unknown("fix_glyphs", unknown, ["require", "grid", "max_move", "depth", "min_severity", "strict", "in_place",
                                       "work", "add_nodes"])
    min_severity = _o.number("min_severity", min_severity, 0.0)
    return _cmr._fix_glyphs(_o.text("source", os.fspath(source)), _o.text("glyphs", glyphs),
                            _o.text("require", require), _o.number("grid", grid, 0.0),
                            0.0 if max_move is None else _o.number("max_move", max_move, 0.0),
                            _o.integer("depth", depth, 0, _o.MAX_DEPTH), -1.0 if strict else min_severity,
                            bool(in_place), _o.integer("work", work, 1, MAX_GLYPH_WORK), bool(add_nodes))


def kcurve(points, *, closed=False, cubic=False, tolerance=1e-10, max_iterations=10000, **unknown):
    """``cmr kcurve POINTS.json [--closed] [--cubic]``: the kappa-curve through
    the points (N x 2) as a cmr.Spline (docs/kcurve.md)."""
    _o.unknown("kcurve", unknown, ["closed", "cubic", "tolerance", "max_iterations"])
    tolerance = _o.number("tolerance", tolerance)
    if not 0 < tolerance < 1:
        raise InputError(f"tolerance: {tolerance} is outside (0, 1)")
    spline, notes = _cmr._kcurve(points, bool(closed), bool(cubic), tolerance,
                                 _o.integer("max_iterations", max_iterations, 1, 1000000))
    _notes(notes)
    return spline


def judge(spline, *, require="cmrwi", depth=DEFAULT_DEPTH, angle_tol=1e-3, curvature_tol=1e-6, **unknown):
    """One spline judged as ``cmr report --require R`` judges it (no regions,
    no fixes): its entry of report.json (docs/report-schema.md), with
    "status" and each gate's violations."""
    _o.unknown("judge", unknown, ["require", "depth", "angle_tol", "curvature_tol"])
    return _cmr._judge(_o.spline(spline, "judge"), _o.text("require", require),
                       _o.integer("depth", depth, 0, _o.MAX_DEPTH), _o.number("angle_tol", angle_tol),
                       _o.number("curvature_tol", curvature_tol))


def judge_many(splines, *, require="cmrwi", depth=DEFAULT_DEPTH, threads=0, **unknown):
    """Many splines judged as ``cmr report --require R`` judges them, in one
    call on `threads` threads (0: every core; report_batch, no regions, no
    fixes): per spline {"name", "status", "gates"} ("gates" as in
    report.json, with each violation). The fast path for many glyph
    contours (cmr.pen.SplinePen.contours)."""
    _o.unknown("judge_many", unknown, ["require", "depth", "threads"])
    items = [_o.spline(s, "judge_many") for s in splines]
    return _cmr._judge_many(items, _o.text("require", require), _o.integer("depth", depth, 0, _o.MAX_DEPTH),
                            _o.integer("threads", threads, 0, 1024))


class JudgeQueue:
    """judge_many in the background, for a script that makes its splines as
    it goes (drawing glyphs through cmr.pen.SplinePen): ``submit(splines)``
    returns at once and the batch is judged on a worker thread (the same
    judging as judge_many, on `threads` threads) while Python goes on;
    ``results()`` waits for every batch submitted so far and returns their
    entries in submission order, as judge_many's list. Ctrl-C in
    ``results()`` raises KeyboardInterrupt and drops the batches not yet
    started.

        q = cmr.JudgeQueue(require="cmrwi")
        for name in names:
            q.submit(cmr.fonttools.glyph_contours(glyphs, name))
        verdicts = q.results()
    """

    def __init__(self, *, require="cmrwi", depth=DEFAULT_DEPTH, threads=0, **unknown):
        _o.unknown("JudgeQueue", unknown, ["require", "depth", "threads"])
        self._queue = _cmr._JudgeQueue(_o.text("require", require), _o.integer("depth", depth, 0, _o.MAX_DEPTH),
                                       _o.integer("threads", threads, 0, 1024))

    def submit(self, splines):
        """Queues these splines (cmr.Spline objects or spline dicts)."""
        self._queue.submit([_o.spline(s, "JudgeQueue.submit") for s in splines])

    def results(self):
        """Every entry submitted so far, judged, in submission order."""
        return self._queue.results()


def report(paths, *, require="", out=None, segments=None, depth=DEFAULT_DEPTH, glyphs="A-Z,a-z",
           location=None, between=None, min_severity=None, severity=True, strict=False, thumbnails=True, fixes=True,
           backend="auto", angle_tol=1e-3, curvature_tol=1e-6, cache=True, **unknown):
    """``cmr report FILES... --out DIR [--require R]``: the batch report of
    spline files, SVG files, fonts and folders (planar; a space curve's file
    raises InputError: its report is the command's). Writes report.json
    and index.html to `out` (a temporary folder, removed again, when None)
    and returns {"exit_code", "summary" (the command's one line), "invalid",
    "pass", "fail", "items", "findings", "report" (report.json as a dict),
    "out"}. thumbnails=False is --no-thumbnails, fixes=False --no-fixes,
    cache=False --no-cache (no report.cache is read or written in `out`).
    glyphs: the fonts' glyphs, "A-Z,a-z", "U+0041-U+005A" or "all" (a font
    source's every glyph). location: a variable font's instance, as
    --location ("wght=700,opsz=14") or a dict {"wght": 700, "opsz": 14};
    None, the default instance (report["settings"]["location"] names it).
    between: the interpolation gates' segment of the design space, as
    --between ("wght=400:wght=700"; None: between adjacent masters).
    min_severity, severity=False, strict=True: --min-severity U,
    --no-severity, --strict (fonts get each finding's severity, and one
    below half a font unit is info, by default: docs/report.md).
    """
    _o.unknown("report", unknown, ["require", "out", "segments", "depth", "glyphs", "location", "between", "min_severity",
                                   "severity", "strict", "thumbnails", "fixes", "backend", "angle_tol",
                                   "curvature_tol", "cache"])
    if isinstance(paths, (str, os.PathLike)):
        paths = [paths]
    a = _cmr._ReportArgs()
    a.files = [os.fspath(p) for p in paths]
    for p in a.files:  # space curves have a report of their own (the command's), not bound here
        if p.lower().endswith(".json") and os.path.isfile(p):
            try:
                dimension = Spline.load(p).dimension
            except InputError:
                continue  # an invalid file: the report names it
            if dimension == 3:
                raise InputError(f"{p} is a space curve: cmr.report takes planar files "
                                 "(cmr report FILES --out DIR reports space curves)")
    a.require = _o.text("require", require)
    a.segments = _o.segment_range(segments)
    a.depth = _o.integer("depth", depth, 0, _o.MAX_DEPTH)
    a.glyphs = _o.text("glyphs", glyphs)
    if isinstance(location, dict):
        location = ",".join(f"{tag}={value}" for tag, value in location.items())
    a.location = "" if location is None else _o.text("location", location)
    a.between = "" if between is None else _o.text("between", between)
    a.min_severity = None if min_severity is None else _o.number("min_severity", min_severity)
    a.severity = bool(severity)
    a.strict = bool(strict)
    a.thumbnails = bool(thumbnails)
    a.fixes = bool(fixes)
    a.cache = bool(cache)
    a.backend = _o.choice("backend", backend, ("auto", "vulkan", "cpu"))
    a.angle_tol = _o.number("angle_tol", angle_tol)
    a.curvature_tol = _o.number("curvature_tol", curvature_tol)

    def run(folder):
        a.out = folder
        result = _cmr._report(a)
        with open(os.path.join(folder, "report.json"), encoding="utf-8") as f:
            result["report"] = json.load(f)
        result["out"] = None if out is None else folder
        return result

    if out is not None:
        return run(os.fspath(out))
    with tempfile.TemporaryDirectory(prefix="cmr-report-") as folder:
        return run(os.path.join(folder, "report"))
