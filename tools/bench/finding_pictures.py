#!/usr/bin/python3
"""Pictures of a font report's most severe and borderline findings (issue 36
item 7; docs/qa-corpus.md "The findings as a designer sees them").

    finding_pictures.py REPORT_DIR UFO OUT_PREFIX [COUNT]

REPORT_DIR is the output of `cmr report UFO --glyphs all --require GATES`
with thumbnails (its font.html has each glyph's outline, curvature comb and
findings in red, as the page shows them) and severity on (report.json has
each finding's severity). Picks the COUNT (default 10) findings with the
largest finite severity and the COUNT whose severity lies nearest the
report's threshold (--min-severity, 0.5 units by default) and draws each
as that glyph's picture from the page, with the finding's node(s) ringed in
magenta and a caption: glyph, contour, node, gate, severity. Writes
OUT_PREFIX-severe.png and OUT_PREFIX-borderline.png (a 5-column sheet each)
and prints the two lists. Needs rsvg-convert and ImageMagick's montage
(Debian librsvg2-bin, imagemagick; installed when missing, as corpus.sh
installs its fonts). A picture tool, not a test.
"""
import html
import json
import math
import os
import plistlib
import re
import shutil
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

report_dir, ufo, prefix = sys.argv[1:4]
count = int(sys.argv[4]) if len(sys.argv) > 4 else 10

for tool, package in (("rsvg-convert", "librsvg2-bin"), ("montage", "imagemagick")):
    if shutil.which(tool) is None:
        sudo = [] if os.geteuid() == 0 else ["sudo"]
        print("finding_pictures: installing %s" % package, file=sys.stderr)
        subprocess.run([*sudo, "apt-get", "install", "-y", "-qq", "--no-install-recommends", package], check=True,
                       env=dict(os.environ, DEBIAN_FRONTEND="noninteractive"), stdout=subprocess.DEVNULL)

doc = json.load(open(os.path.join(report_dir, "report.json"), encoding="utf-8"))
page = open(os.path.join(report_dir, "font.html"), encoding="utf-8").read()
threshold = 0.5
findings = []  # (severity, glyph, contour, node, gate, message)
for sp in doc["splines"]:
    for f in sp.get("findings", []):
        s = f.get("severity")
        if s is None or not math.isfinite(s):
            continue
        findings.append((s, sp["glyph"], sp["contour"], f.get("node", ""), f["gate"], f["message"]))


def distinct(ordered):
    """The first `count` findings that differ by more than their glyph and
    place: an accented glyph's copy of its base letter's contour (D, Dcaron,
    Eth) has the same finding with the same severity, shown once."""
    seen, out = set(), []
    for f in ordered:
        # The message without the glyph, contour, point names and places.
        what = re.sub(r"^\S+/c\d+ |p\d+|joint \d+|segment \d+|t = [\d.]+", "", f[5])
        key = (round(f[0], 6), f[4], what)
        if key in seen:
            continue
        seen.add(key)
        out.append(f)
        if len(out) == count:
            break
    return out


severe = distinct(sorted(findings, key=lambda f: -f[0]))
borderline = distinct(sorted(findings, key=lambda f: (abs(f[0] - threshold), f[1])))

# The UFO's points, in the .glif's own order (the names p<k> count them).
contents = plistlib.load(open(os.path.join(ufo, "glyphs", "contents.plist"), "rb"))


def glif_points(glyph):
    root = ET.parse(os.path.join(ufo, "glyphs", contents[glyph])).getroot()
    out = []
    for c in root.iter("contour"):
        out.append([(float(p.get("x")), float(p.get("y"))) for p in c.iter("point")])
    return out


def node_places(glyph, contour, node):
    """Font-unit positions of a finding's node names: p<k>, p<a>+p<b> (an
    implied point halfway), p<a>-p<b> (a piece between two nodes)."""
    pts = glif_points(glyph)[contour]
    places = []
    for part in node.split("-"):
        ks = [int(k) for k in re.findall(r"p(\d+)", part)]
        if not ks or "@" in part or any(k >= len(pts) for k in ks):
            continue
        places.append((sum(pts[k][0] for k in ks) / len(ks), sum(pts[k][1] for k in ks) / len(ks)))
    return places


def glyph_svg(glyph, places):
    """The glyph's first picture on the page (outline, comb, findings in red),
    standalone, with rings at `places`."""
    start = page.find('<section id="g0-%s">' % html.escape(glyph, quote=True))
    if start < 0:
        return None
    m = re.search(r"<svg [^>]*viewBox=\"([-\d. ]+)\"[^>]*>(.*?)</svg>", page[start:], re.S)
    vb = [float(v) for v in m.group(1).split()]
    r = vb[2] / 30
    rings = "".join('<circle cx="%g" cy="%g" r="%g" fill="none" stroke="#e000e0" stroke-width="3" '
                    'vector-effect="non-scaling-stroke"/>' % (x, -y, r) for x, y in places)
    return ('<svg xmlns="http://www.w3.org/2000/svg" width="260" height="260" viewBox="%s">'
            '<rect x="%g" y="%g" width="%g" height="%g" fill="#fff"/>%s%s</svg>'
            % (m.group(1), vb[0], vb[1], vb[2], vb[3], m.group(2), rings))


def sheet(items, out):
    with tempfile.TemporaryDirectory() as tmp:
        args = []
        for i, (s, glyph, contour, node, gate, _) in enumerate(items):
            svg = glyph_svg(glyph, node_places(glyph, contour, node))
            if svg is None:
                continue
            src, png = os.path.join(tmp, "%02d.svg" % i), os.path.join(tmp, "%02d.png" % i)
            open(src, "w", encoding="utf-8").write(svg)
            subprocess.run(["rsvg-convert", "-w", "260", "-h", "260", "-o", png, src], check=True)
            args += ["-label", "%s c%d %s\n%s %.2f" % (glyph, contour, node, gate.split(":")[0], s), png]
        subprocess.run(["montage", *args, "-tile", "5x", "-geometry", "+6+6", "-pointsize", "12", "+dither", "-colors", "64", out],
                       check=True)


for name, items in (("severe", severe), ("borderline", borderline)):
    out = "%s-%s.png" % (prefix, name)
    sheet(items, out)
    print("## %s (%s)" % (name, out))
    for s, glyph, contour, node, gate, message in items:
        print("- %.3f  %s c%d %s  %s: %s" % (s, glyph, contour, node, gate, message))
