#!/usr/bin/python3
"""cmr's g1-between-masters against the midway kink heuristic, judged by
exact arithmetic (issue 37 item 3; the table in docs/interpolation.md).

    /usr/bin/python3 tools/bench/midway_compare.py [--cmr build/tools/cmr]
        [--font FONT.ttf ... | --no-font] [--pictures docs/img]

For each case (a two-master designspace written into a temporary folder by
tools/make_test_designspace.py's writers, glyph "O", node p0 at (0, 0) with
incoming tangent u = p0 - (the point before) and outgoing v = (the point
after) - p0 at each master), it runs

  * the baseline: tools/bench/midway_kinks.py --json (the midway-instance
    heuristic: thresholds, the halfway instance only);
  * cmr: `cmr report CASE.designspace --require g1-between-masters`
    (report.json's findings at p0);
  * the exact reference, here in fractions.Fraction, independent of both.
    Between the masters u(s) = (1 - s) uA + s uB, v likewise, so
        c(s) = u x v,  d(s) = u . v      (polynomials of degree <= 2 in s)
    and the turn at the node is theta(s) = atan2(c, d). The node is G1 at
    every instance iff c == 0 identically and d > 0 on [0, 1]. |theta| is
    largest on (0, 1) at a root of g = c'd - cd' (degree <= 2: the s^3
    terms cancel), isolated here by exact sign bisection to 2^-60; the
    angle there is evaluated in double precision. A node exactly G1 at
    both masters is a kink between them iff c is not identically zero (any
    angle: cmr's gate) or d <= 0 somewhere (the tangents reverse). A node that is not exactly G1 at a master is a
    corner there; the reference gives its turn at the masters and the
    largest turn between.

It prints the Markdown table (one row per case: what each tool says, the
exact answer, who is right), then (unless --no-font) the same three on a
variable font's real masters (--font, repeatable; Debian's Inter roman and
italic by default): every on-curve node with an off-curve
neighbour of its Latin letters, on each piece between adjacent masters.
--pictures DIR draws each case (both masters and the worst instance, the
node's tangents) as DIR/midway_CASE.svg. Exit 1 when cmr's answer differs
from the exact one on a case (a check, not a threshold on the baseline).
"""

import argparse
import json
import math
import os
import re
import subprocess
import sys
import tempfile
import time
from collections import Counter
from fractions import Fraction as F

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
sys.path.insert(0, HERE)
import make_test_designspace as mtd  # noqa: E402  (tools/: the fixture's writers)
import midway_kinks  # noqa: E402

# ----------------------------------------------------------------- exact


def cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1]


def lerp(a, b, s):
    return (a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]))


def power(uA, vA, uB, vB, f):
    """f(u(s), v(s)) (cross or dot) as power coefficients [p0, p1, p2]."""
    du, dv = (uB[0] - uA[0], uB[1] - uA[1]), (vB[0] - vA[0], vB[1] - vA[1])
    return [f(uA, vA), f(uA, dv) + f(du, vA), f(du, dv)]


def ev(p, s):
    return p[0] + s * (p[1] + s * p[2])


def sgn(x):
    return (x > 0) - (x < 0)


def roots01(p):
    """Brackets (lo, hi), hi - lo <= 2^-60, of the roots of p (degree <= 2,
    not identically zero) in the open interval (0, 1), by exact bisection on
    the monotone parts of [0, 1]."""
    cuts = [F(0), F(1)]
    if p[2] != 0:
        crit = -p[1] / (2 * p[2])
        if 0 < crit < 1:
            cuts.insert(1, crit)
    out = []
    for lo, hi in zip(cuts, cuts[1:]):
        a, b = sgn(ev(p, lo)), sgn(ev(p, hi))
        if a == 0 or b == 0:
            for x in ((lo,) if a == 0 else ()) + ((hi,) if b == 0 else ()):
                if 0 < x < 1 and (x, x) not in out:
                    out.append((x, x))
            continue
        if a == b:
            continue
        while hi - lo > F(1, 2**60):
            m = (lo + hi) / 2
            sm = sgn(ev(p, m))
            if sm == 0:
                lo = hi = m
                break
            if sm == a:
                lo = m
            else:
                hi = m
        out.append((lo, hi))
    return out


def turn_deg(c, d, s):
    return math.degrees(math.atan2(float(ev(c, s)), float(ev(d, s))))


def reference(uA, vA, uB, vB):
    """The exact answer at one node between two masters (see the docstring)."""
    uA, vA, uB, vB = ([F(x) for x in p] for p in (uA, vA, uB, vB))
    c, d = power(uA, vA, uB, vB, cross), power(uA, vA, uB, vB, dot)
    g1_a = c[0] == 0 and d[0] > 0
    g1_b = ev(c, 1) == 0 and ev(d, 1) > 0
    ends = (turn_deg(c, d, F(0)), turn_deg(c, d, F(1)))
    out = {"g1_at_masters": g1_a and g1_b, "ends": ends, "worst": 0.0, "worst_s": None}
    # |theta| on (0, 1): its largest value lies at a root of g = c'd - cd' (or at an end).
    dc, dd = [c[1], 2 * c[2]], [d[1], 2 * d[2]]
    g = [dc[0] * d[0] - c[0] * dd[0], dc[0] * d[1] + dc[1] * d[0] - c[0] * dd[1] - c[1] * dd[0],
         dc[0] * d[2] + dc[1] * d[1] - c[1] * dd[1] - c[2] * dd[0]]
    # The tangents reverse (or a handle collapses) where d <= 0: d's least value on [0, 1], exactly.
    lows = [ev(d, F(0)), ev(d, F(1))]
    if d[2] > 0 and 0 < -d[1] / (2 * d[2]) < 1:
        lows.append(ev(d, -d[1] / (2 * d[2])))
    reverses = min(lows) <= 0
    if any(g):
        for lo, hi in roots01(g):
            m = (lo + hi) / 2
            a = abs(turn_deg(c, d, m))
            if a > out["worst"]:
                out["worst"], out["worst_s"] = a, float(m)
                u, v = lerp(uA, uB, m), lerp(vA, vB, m)
                chord = math.hypot(float(u[0] + v[0]), float(u[1] + v[1]))
                out["deviation"] = abs(float(cross(u, v))) / chord if chord else 0.0
    if reverses and not any(c):
        out["worst"] = 180.0  # collinear throughout, pointing against each other somewhere
        zeros = roots01(d) if any(d) else []
        out["worst_s"] = float(zeros[0][0]) if zeros else 0.0
        out["deviation"] = 0.0
    out["kink"] = (any(c) or reverses) if out["g1_at_masters"] else None
    out["reverses"] = reverses
    out["growth"] = max(0.0, out["worst"] - max(abs(ends[0]), abs(ends[1])))
    return out


# ----------------------------------------------------------------- cases

BASE = {"b": (0, 400), "h": (300, 400), "k": (-300, 400)}
# (name, kind, what it shows, Regular's (u, v), Bold's (u, v), marked smooth)
CASES = [
    ("both-a", "both", "handles 1:3 become 2:1 while the node turns 45 degrees",
     ((100, 0), (300, 0)), ((100, 100), (50, 50)), True),
    ("both-b", "both", "handles 1:3 become 2:1 while the node turns 53 degrees",
     ((100, 0), (300, 0)), ((60, 80), (30, 40)), True),
    ("example", "missed", "examples/interpolation/Family.designspace: a 4.6 degree kink, below the 12 degree threshold",
     ((100, 0), (200, 0)), ((60, 30), (240, 120)), True),
    ("below", "missed", "12.1 degrees at the halfway instance, just under the threshold (sine 0.209 x 0.475 <= 0.1)",
     ((200, 0), (100, 0)), ((120, 160), (150, 200)), True),
    ("early-a", "missed", "short handles at Regular, long at Bold: the kink is near Regular, small at s = 1/2",
     ((20, 0), (10, 0)), ((60, 240), (240, 960)), True),
    ("early-b", "missed", "the same with handles 3:1 becoming 1:4",
     ((30, 0), (10, 0)), ((40, 160), (160, 640)), True),
    ("alike", "missed", "handle proportions 0.5 and 0.588 (differing by less than 0.1: 'smooth enough') while the node turns 127 degrees",
     ((100, 0), (100, 0)), ((-60, 80), (-42, 56)), True),
    ("large", "missed", "a 53 degree kink: its deviation is more than 0.1 of the chord, taken as intended",
     ((100, 0), (300, 0)), ((0, 300), (0, 100)), True),
    ("proportional", "neither", "examples/interpolation/Proportional.designspace: handles 1:2 at both masters",
     ((100, 0), (200, 0)), ((60, 30), (120, 60)), True),
    ("corner-a", "flagged, not smooth", "a corner (not marked smooth) of 5.0 and 4.0 degrees at the masters, turning 16 degrees between",
     ((100, 0), (299, 26)), ((100, 100), (40, 46)), False),
    ("corner-b", "flagged, not smooth", "a corner of 5.0 degrees at Regular, -4.0 at Bold, turning 18.6 degrees between",
     ((100, 0), (299, 26)), ((100, 100), (46, 40)), False),
    ("rounded", "cmr misses", "marked smooth but 0.19 and 0.57 degrees off at the masters (integer rounding), 19 degrees between",
     ((100, 0), (300, 1)), ((100, 100), (50, 51)), True),
]


# The turn of g1-between-masters:DEG in the tables' last cmr column.
TURN = 1.0
DEFAULT_FONTS = ["/usr/share/fonts/truetype/inter-vf/Inter-roman.var.ttf",
                 "/usr/share/fonts/truetype/inter-vf/Inter-italic.var.ttf"]
# Two cases of each kind get a picture (docs/interpolation.md).
PICTURES = ("both-a", "both-b", "early-a", "alike", "corner-a", "corner-b", "rounded")


def write_case(out, name, reg, bold, smooth):
    def master(uv):
        return dict(BASE, u=uv[0], v=uv[1], smooth=smooth)

    mtd.ufo(os.path.join(out, name + "-Regular.ufo"), "Regular", master(reg))
    mtd.ufo(os.path.join(out, name + "-Bold.ufo"), "Bold", master(bold))
    mtd.designspace(out, name, name + "-Bold.ufo", regular=name + "-Regular.ufo")
    return os.path.join(out, name + ".designspace")


def run_midway(source, glyphs=None):
    cmd = [sys.executable, os.path.join(HERE, "midway_kinks.py"), source, "--json"]
    if glyphs:
        cmd += ["--glyphs", glyphs]
    r = subprocess.run(cmd, capture_output=True, text=True, check=True)
    return json.loads(r.stdout)


def run_cmr(cmr, source, out, gates="g1-between-masters", glyphs="O"):
    t0 = time.perf_counter()
    r = subprocess.run([cmr, "report", source, "--require", gates, "--glyphs", glyphs, "--no-thumbnails", "-j", "2",
                        "--out", out], capture_output=True, text=True)
    seconds = time.perf_counter() - t0
    if r.returncode not in (0, 1) and not (r.returncode == 2 and os.path.exists(os.path.join(out, "report.json"))):
        raise SystemExit(f"midway_compare: cmr exited {r.returncode}: {r.stderr.strip()}")
    with open(os.path.join(out, "report.json")) as f:
        rep = json.load(f)
    findings = [fd for s in rep["splines"] for fd in s.get("findings", []) if fd["gate"] == gates.split(",")[0]]
    return r.returncode, findings, seconds


WORST = re.compile(r"worst ([0-9.e+-]+) degrees at \{([^}]*)\} \(s = ([0-9.e+-]+)\)")


def weight_of(s):
    """The user Weight at s of the fixture's axis (design 40..120, user 400..700: linear)."""
    return mtd.USER[0] + s * (mtd.USER[1] - mtd.USER[0])


def fmt_case(name, kind, what, reg, bold, smooth, cmr, tmp, pictures):
    ds = write_case(tmp, name, reg, bold, smooth)
    mid = [k for k in run_midway(ds)["kinks"] if k["point"] == 0]
    rc, found, _ = run_cmr(cmr, ds, os.path.join(tmp, name + "-qa"))
    found = [f for f in found if f["node"] == "p0"]
    rc_t, found_t, _ = run_cmr(cmr, ds, os.path.join(tmp, name + "-qa-t"), gates=f"g1-between-masters:{TURN:g}")
    found_t = [f for f in found_t if f["node"] == "p0"]
    ref = reference(reg[0], reg[1], bold[0], bold[1])
    # What each says.
    if mid:
        m = mid[0]
        mid_says = f"kink (sine {abs(m['sin_mid']):.3f} at s = 1/2, {m['deviation']:.1f} units)"
    else:
        mid_says = "nothing"
    if found:
        w = WORST.search(found[0]["message"])
        cmr_says = f"exit {rc}: kink, worst {float(w.group(1)):.2f} deg at Weight {float(w.group(2).split(':')[1]):.1f}"
    else:
        cmr_says = f"exit {rc}: " + ("G1 throughout" if ref["g1_at_masters"] else "not judged (not G1 at the masters)")
    if ref["g1_at_masters"]:
        if ref["kink"]:
            exact = (f"kink on (0, 1): worst {ref['worst']:.2f} deg at s = {ref['worst_s']:.3f} "
                     f"(Weight {weight_of(ref['worst_s']):.1f}), {ref['deviation']:.1f} units")
        else:
            exact = "G1 at every instance (u x v = 0)"
    else:
        exact = (f"not G1 at the masters ({ref['ends'][0]:.2f}, {ref['ends'][1]:.2f} deg); "
                 f"{ref['worst']:.2f} deg at s = {ref['worst_s']:.3f}")
    if found_t:
        w = WORST.search(found_t[0]["message"])
        turn_says = f"exit {rc_t}: turns beyond {TURN:g} deg, worst {float(w.group(1)):.2f}"
    else:
        turn_says = f"exit {rc_t}: " + ("judged, within" if smooth and within(ref, TURN) else "not judged")
    # The turn column against the reference: judged (marked smooth, within TURN at both masters) and beyond it.
    turn_ok = bool(found_t) == (smooth and within(ref, TURN) and ref["worst"] > TURN)
    # Who is right.
    truth_kink = bool(ref["kink"]) if ref["g1_at_masters"] else None
    cmr_ok = (bool(found) == truth_kink) if truth_kink is not None else not found
    if found and ref["worst_s"] is not None:
        w = WORST.search(found[0]["message"])
        cmr_ok = cmr_ok and abs(float(w.group(1)) - ref["worst"]) < 1e-4 and abs(float(w.group(3)) - ref["worst_s"]) < 1e-9
    if truth_kink is None:
        if smooth:
            right = (f"midway, and cmr with :{TURN:g}; the exact rule is silent (the node is not exactly G1 at the "
                     "masters)")
            cmr_ok = True  # cmr's rule (exactly G1 at both masters) says: not judged; the check is on its own terms
        elif mid:
            right = "cmr: the node is a corner at both masters, not a smooth node"
        else:
            right = "both (a corner)"
    elif truth_kink:
        right = "both" if mid and found else ("cmr" if found else "midway")
    else:
        right = "both" if not mid and not found else ("cmr" if not found else "midway")
    if pictures and name in PICTURES:
        draw(os.path.join(pictures, f"midway_{name}.svg"), name, reg, bold, ref["worst_s"])
    return (f"| `{name}` | {kind} | {what} | {mid_says} | {cmr_says} | {turn_says} | {exact} | {right} |",
            cmr_ok and turn_ok)


# ----------------------------------------------------------------- pictures


def draw(path, name, reg, bold, worst_s):
    """Three columns: the glyph at Regular, at the worst instance between
    (the exact reference's s) and at Bold, each with node p0's handles; the
    contour is the fixture's (make_test_designspace.glyph_o). Below each, the
    node close up: its two tangent directions and the turn between them."""
    panels = [("Regular (s = 0)", 0.0), (f"worst, s = {worst_s:.3f}" if worst_s is not None else "halfway", worst_s
                                           if worst_s is not None else 0.5), ("Bold (s = 1)", 1.0)]
    w, h, pad, zoom = 220, 240, 14, 150
    pts = []
    for _, s in panels:
        u, v = lerp(reg[0], bold[0], s), lerp(reg[1], bold[1], s)
        pts.append(((0, 0), v, BASE["h"], BASE["b"], BASE["k"], (-u[0], -u[1])))
    xs = [p[0] for ps in pts for p in ps]
    ys = [p[1] for ps in pts for p in ps]
    lo_x, hi_x, lo_y, hi_y = min(xs), max(xs), min(ys), max(ys)
    k = min((w - 2 * pad) / (hi_x - lo_x), (h - 3 * pad) / (hi_y - lo_y))

    def xy(p, i):
        return f"{i * w + pad + (p[0] - lo_x) * k:.1f},{pad + (hi_y - p[1]) * k:.1f}"

    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{3 * w}" height="{h + zoom}" '
           f'viewBox="0 0 {3 * w} {h + zoom}">', f'<rect width="{3 * w}" height="{h + zoom}" fill="white"/>']
    for i, ((label, s), (p0, v, hh, b, kk, pu)) in enumerate(zip(panels, pts)):
        colour = "#c00" if i == 1 else "#222"
        out.append(f'<path d="M{xy(p0, i)} C{xy(v, i)} {xy(hh, i)} {xy(b, i)} C{xy(kk, i)} {xy(pu, i)} {xy(p0, i)}Z" '
                   f'fill="none" stroke="{colour}" stroke-width="1.5"/>')
        out.append(f'<polyline points="{xy(pu, i)} {xy(p0, i)} {xy(v, i)}" fill="none" stroke="#07c" stroke-width="1"/>')
        for p in (pu, v):
            out.append(f'<circle cx="{xy(p, i).split(",")[0]}" cy="{xy(p, i).split(",")[1]}" r="2.5" fill="#07c"/>')
        c = xy(p0, i).split(",")
        out.append(f'<circle cx="{c[0]}" cy="{c[1]}" r="3" fill="{colour}"/>')
        out.append(f'<text x="{i * w + pad}" y="{h - 6}" font-size="12" font-family="sans-serif">{label}</text>')
        # The node close up: both handles scaled to 60 px, and the turn between them.
        cx, cy, z = i * w + w / 2, h + zoom / 2, 60
        ends = []
        for q in (pu, v):
            length = math.hypot(q[0], q[1]) or 1
            ends.append((cx + q[0] / length * z, cy - q[1] / length * z))
        out.append(f'<polyline points="{ends[0][0]:.1f},{ends[0][1]:.1f} {cx:.1f},{cy:.1f} {ends[1][0]:.1f},'
                   f'{ends[1][1]:.1f}" fill="none" stroke="{colour}" stroke-width="2"/>')
        turn = math.degrees(math.atan2(cross((-pu[0], -pu[1]), v), dot((-pu[0], -pu[1]), v)))
        out.append(f'<text x="{i * w + pad}" y="{h + zoom - 6}" font-size="12" font-family="sans-serif">'
                   f'turn at p0: {turn:.2f} deg</text>')
    out.append(f'<text x="{3 * w - pad}" y="{pad}" font-size="12" font-family="sans-serif" '
               f'text-anchor="end">{name}: node p0 and its handles</text>')
    out.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


# ----------------------------------------------------------------- a real font


def font_nodes(path, names):
    """Per piece between adjacent masters of a gvar font (the midway
    baseline's masters and pairs): (piece label, glyph name, contour, point,
    tangents at both masters, two lines?) of every on-curve node whose
    neighbours differ from it, integer coordinates as fontTools
    instantiates them (FreeType's too: the deltas are integers)."""
    _, masters, glyphs = midway_kinks.variable_font_masters(path, names)
    for i, j in midway_kinks.pairs(masters):
        for g in glyphs:
            a, b = masters[i][2].get(g), masters[j][2].get(g)
            if a is None or b is None or len(a) != len(b):
                continue
            for ci, ((pa, on), (pb, onb)) in enumerate(zip(a, b)):
                if len(pa) != len(pb) or on != onb:
                    continue
                n = len(pa)
                for k in range(n):
                    p, q = (k - 1) % n, (k + 1) % n
                    if not on[k]:
                        continue
                    t = [(pa[k][0] - pa[p][0], pa[k][1] - pa[p][1]), (pa[q][0] - pa[k][0], pa[q][1] - pa[k][1]),
                         (pb[k][0] - pb[p][0], pb[k][1] - pb[p][1]), (pb[q][0] - pb[k][0], pb[q][1] - pb[k][1])]
                    if any(x == (0, 0) for x in t):
                        continue
                    yield f"{masters[i][0]}:{masters[j][0]}", g, ci, k, t, on[p] and on[q]


def within(ref, deg):
    return abs(ref["ends"][0]) <= deg and abs(ref["ends"][1]) <= deg


def cmr_keys(out, gate):
    """Counter of (glyph, contour, node) of a cmr report's findings of `gate`,
    and the glyphs it did not judge (invalid)."""
    with open(os.path.join(out, "report.json")) as f:
        rep = json.load(f)
    keys = Counter((sp["glyph"], sp["contour"], fd["node"]) for sp in rep["splines"] for fd in sp.get("findings", [])
                   if fd["gate"] == gate)
    invalid = {sp["glyph"] for sp in rep["splines"] if sp["status"] == "invalid"}
    return keys, invalid


def font_rows(path, cmr, tmp, everything):
    """One row of the font table (the Latin letters, or with `everything`
    every character), and whether cmr's findings are the exact reference's."""
    from fontTools.ttLib import TTFont

    cmap = TTFont(path).getBestCmap()
    names = ["all"] if everything else []
    glyphs = "all" if everything else "A-Z,a-z"
    wanted = None if everything else {cp for cp in cmap if 0x41 <= cp < 0x7B and chr(cp).isalpha()}
    by_name = {}
    for cp, name in cmap.items():
        if wanted is None or cp in wanted:
            by_name.setdefault(name, []).append(name)  # cmr reads each character, labelled by its glyph's name
    mid = run_midway(path, "all" if everything else None)
    gate_t = f"g1-between-masters:{TURN:g}"
    rc, _, t_cmr = run_cmr(cmr, path, os.path.join(tmp, f"font-qa-{glyphs}"), glyphs=glyphs)
    got, invalid = cmr_keys(os.path.join(tmp, f"font-qa-{glyphs}"), "g1-between-masters")
    rc_t, _, t_turn = run_cmr(cmr, path, os.path.join(tmp, f"font-qa-t-{glyphs}"), gates=gate_t, glyphs=glyphs)
    got_t, _ = cmr_keys(os.path.join(tmp, f"font-qa-t-{glyphs}"), gate_t)
    c = Counter()
    want, want_t, big = Counter(), Counter(), []
    worst = (0.0, None)
    for piece, g, ci, k, (uA, vA, uB, vB), lines in font_nodes(path, names):
        shown = [u for u in by_name.get(g, []) if u not in invalid]  # the glyph once per character
        if not shown:
            continue
        ref = reference(uA, vA, uB, vB)
        if within(ref, TURN):  # what g1-between-masters:TURN judges (a variable font has no smooth marks)
            c["turn"] += 1
            if ref["worst"] > TURN:
                want_t.update((u, ci, f"p{k}") for u in shown)
        if ref["g1_at_masters"]:
            c["exact"] += 1
            if ref["kink"]:
                want.update((u, ci, f"p{k}") for u in shown)
                c["reverse"] += ref["reverses"]
                if ref["worst"] > 1 and not ref["reverses"]:
                    big.append((ref["worst"], f"{g}/c{ci}/p{k}"))
        if lines:
            continue  # two lines: not a node the baseline looks at
        c["nodes"] += 1
        if ref["g1_at_masters"]:
            continue
        sa, sb = (math.sin(math.radians(abs(e))) for e in ref["ends"])
        if sa <= midway_kinks.T and sb <= midway_kinks.T and abs(ref["ends"][0]) < 90 and abs(ref["ends"][1]) < 90:
            c["near"] += 1
            for limit in (1, 5, 12):
                c[f"grows{limit}"] += ref["growth"] > limit
            if ref["growth"] > worst[0]:
                worst = (ref["growth"], f"{g}/c{ci}/p{k} ({piece}): {max(abs(e) for e in ref['ends']):.2f} deg at the "
                         f"masters, {ref['worst']:.2f} between")
    name = os.path.basename(path)
    n_kinks = sum(want.values())
    big.sort(reverse=True)
    n_chars = sum(len(v) for v in by_name.values())
    details = ([f"{c['reverse']} where the tangents reverse"] if c["reverse"] else []) + (
        [f"{len(big)} over 1 degree, worst {big[0][0]:.2f} at {big[0][1]}"] if big else [])
    row = (f"| {name}: {'every character' if everything else 'Latin letters'} ({n_chars} characters, "
           f"{len(by_name)} glyphs), "
           f"{c['nodes']} on-curve nodes with a handle, on 2 pieces | "
           f"{len(mid['kinks'])} kinks ({mid['seconds']:.2f} s) | "
           f"exit {rc}, {sum(got.values())} findings ({t_cmr:.2f} s) | exit {rc_t}, {sum(got_t.values())} findings "
           f"({t_turn:.2f} s) | "
           f"{c['exact']} nodes (lines too) exactly G1 at both masters, {n_kinks} of them kinks between"
           + (f" ({'; '.join(details)})" if details else "")
           + f"; {c['near']} more within the baseline's smooth threshold, not exactly G1: the turn grows between the "
           f"masters by more than 1 degree at {c['grows1']}, 5 at {c['grows5']}, 12 at {c['grows12']}; "
           f"{c['turn']} nodes (lines too) within {TURN:g} degree at both masters, {sum(want_t.values())} of them beyond it "
           f"between |")
    ok = got == want and got_t == want_t
    if not ok:
        print(f"midway_compare: {name}: cmr's findings differ from the exact reference: cmr only "
              f"{sorted((got - want) + (got_t - want_t))[:5]}, reference only {sorted((want - got) + (want_t - got_t))[:5]}",
              file=sys.stderr)
    notes = []
    if worst[1]:
        notes.append(f"Largest growth of a near-smooth node's turn on {name}: {worst[1]}.")
    if invalid:
        notes.append(f"{name}: cmr's reader refused {len(invalid)} glyphs ({', '.join(sorted(invalid))}); "
                     "they are left out of the reference too.")
    return row, notes, ok


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cmr", default=os.path.join(HERE, "..", "..", "build", "tools", "cmr"))
    ap.add_argument("--font", action="append", help="a gvar variable font (repeatable; default: Inter roman and italic)")
    ap.add_argument("--no-font", action="store_true", help="only the synthetic cases")
    ap.add_argument("--pictures", default="")
    args = ap.parse_args()
    if not os.access(args.cmr, os.X_OK):
        print(f"midway_compare: {args.cmr}: no cmr binary (build it, or give --cmr)", file=sys.stderr)
        return 3
    ok = True
    with tempfile.TemporaryDirectory() as tmp:
        print(f"| case | kind | what | midway (s = 1/2) | cmr g1-between-masters | cmr g1-between-masters:{TURN:g} | "
              "exact (Fraction) | right |")
        print("|---|---|---|---|---|---|---|---|")
        for name, kind, what, reg, bold, smooth in CASES:
            row, good = fmt_case(name, kind, what, reg, bold, smooth, args.cmr, tmp, args.pictures)
            ok = ok and good
            print(row)
        fonts = [] if args.no_font else [f for f in args.font or DEFAULT_FONTS if os.path.exists(f)]
        notes = []
        if fonts:
            print()
            print(f"| font | midway | cmr g1-between-masters | cmr g1-between-masters:{TURN:g} | exact (Fraction) |")
            print("|---|---|---|---|---|")
        for f in fonts:
            for everything in (False, True):
                row, note, good = font_rows(f, args.cmr, tmp, everything)
                ok = ok and good
                print(row)
                notes += note
        for note in notes:
            print("\n" + note)
    if not ok:
        print("midway_compare: cmr's answer differs from the exact one on a case", file=sys.stderr)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
