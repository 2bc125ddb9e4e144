#!/usr/bin/env python3
"""Per-font findings of a corpus run (tools/bench/corpus.sh): from its JUnit
file (glyphs per font) and SARIF file (which glyphs fail which gate), a
Markdown table and an SVG scatter plot: per font, the share of glyphs with a
curvature extremum between nodes (curvature-extrema-at-nodes) against the share whose
runs between on-curve points are not unimodal (curvature-extrema-at-nodes:runs).

Usage: corpus_stats.py JUNIT SARIF TABLE.md PLOT.svg   (standard library only)
"""
import json
import os
import sys
import urllib.parse
import xml.etree.ElementTree as ET

junit, sarif, table, plot = sys.argv[1:5]

fonts = {}  # path -> {"glyphs": n, gate -> set(glyph)}
for suite in ET.parse(junit).getroot():
    fonts[suite.get("name")] = {"glyphs": int(suite.get("tests")), "errors": int(suite.get("errors"))}
with open(sarif, encoding="utf-8") as f:
    log = json.load(f)
for r in log["runs"][0]["results"]:
    uri = r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"]
    path = urllib.parse.unquote(uri[len("file://"):] if uri.startswith("file://") else uri)
    glyph = r.get("properties", {}).get("glyph")
    if path in fonts and glyph is not None:
        rule = r["ruleId"].split(":0")[0]  # g2-at-smooth-nodes:0.05 -> g2-at-smooth-nodes
        fonts[path].setdefault(rule, set()).add(glyph)

rows = []
for path, d in sorted(fonts.items()):
    n = d["glyphs"]
    if n == 0:
        continue
    name = os.path.basename(path)
    cff = name.endswith(".otf")
    share = lambda g: len(d.get(g, ())) / n
    rows.append((name, cff, n, share("curvature-extrema-at-nodes"), share("curvature-extrema-at-nodes:runs"), share("g2-at-smooth-nodes")))

with open(table, "w", encoding="utf-8") as f:
    f.write("| font | outlines | Latin glyphs | curvature-extrema-at-nodes | curvature-extrema-at-nodes:runs | g2-at-smooth-nodes |\n")
    f.write("|---|---|---:|---:|---:|---:|\n")
    for name, cff, n, a, b, c in rows:
        f.write(f"| {name} | {'CFF' if cff else 'TrueType'} | {n} | {a:.0%} | {b:.0%} | {c:.0%} |\n")
    for label, sel in (("TrueType", False), ("CFF", True)):
        rs = [r for r in rows if r[1] == sel]
        g = sum(r[2] for r in rs)
        if g:
            w = lambda k: sum(r[2] * r[k] for r in rs) / g
            f.write(f"| **all {label} ({len(rs)} fonts)** | | {g} | {w(3):.0%} | {w(4):.0%} | {w(5):.0%} |\n")

# The plot: one dot per font (area ~ glyphs), TrueType blue, CFF orange.
W, H, M = 520, 440, 60
def px(x): return M + x * (W - M - 20)
def py(y): return H - M - y * (H - M - 20)
svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="12">',
       f'<rect width="{W}" height="{H}" fill="white"/>']
for t in range(0, 11, 2):
    v = t / 10
    svg.append(f'<line x1="{px(v):.1f}" y1="{py(0)}" x2="{px(v):.1f}" y2="{py(1)}" stroke="#eee"/>')
    svg.append(f'<line x1="{px(0)}" y1="{py(v):.1f}" x2="{px(1)}" y2="{py(v):.1f}" stroke="#eee"/>')
    svg.append(f'<text x="{px(v):.1f}" y="{py(0) + 16}" text-anchor="middle">{t * 10}%</text>')
    svg.append(f'<text x="{px(0) - 6}" y="{py(v) + 4:.1f}" text-anchor="end">{t * 10}%</text>')
svg.append(f'<line x1="{px(0)}" y1="{py(0)}" x2="{px(1)}" y2="{py(1)}" stroke="#bbb" stroke-dasharray="4 3"/>')
for name, cff, n, a, b, c in rows:
    r = max(2.0, (n / 300) ** 0.5 * 5)
    colour = "#e07000" if cff else "#2a62a8"
    svg.append(f'<circle cx="{px(a):.1f}" cy="{py(b):.1f}" r="{r:.1f}" fill="{colour}" fill-opacity="0.5"><title>{name}</title></circle>')
svg.append(f'<text x="{(px(0) + px(1)) / 2}" y="{H - 18}" text-anchor="middle">glyphs with a curvature extremum between nodes (curvature-extrema-at-nodes)</text>')
svg.append(f'<text transform="translate(16 {(py(0) + py(1)) / 2}) rotate(-90)" text-anchor="middle">glyphs with a run that is not unimodal (:runs)</text>')
svg.append(f'<circle cx="{px(0.05)}" cy="{py(0.95)}" r="5" fill="#2a62a8"/><text x="{px(0.05) + 10}" y="{py(0.95) + 4}">TrueType (fonts-noto-core)</text>')
svg.append(f'<circle cx="{px(0.05)}" cy="{py(0.88)}" r="5" fill="#e07000"/><text x="{px(0.05) + 10}" y="{py(0.88) + 4}">CFF (fonts-texgyre)</text>')
svg.append("</svg>\n")
with open(plot, "w", encoding="utf-8") as f:
    f.write("\n".join(svg))
