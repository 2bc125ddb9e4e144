#!/usr/bin/python3
"""Every A-Z a-z glyph of many fonts through `cmr fix` (docs/fix.md, the
dated font tables of issue 36).

    fonts_fix_bench.py CMR OUT_DIR [FONT ...] [--gates G] [--work N] [--add-nodes]

FONT: a name of FONTS below (default: all twelve) or NAME=PATH. For each
font a UFO is made by tools/make_test_ufo.py, then `cmr fix UFO --glyph G
--require GATES --out OUT_DIR/FONT/G.ufo` runs for each glyph (GATES:
curvature-extrema-at-nodes,g2-at-smooth-nodes by default; --work N and
--add-nodes are passed on). Each glyph is one of:
  - pass: exit 0, every contour already passes;
  - fixed: exit 0, a fix written; its total squared move (font units^2),
    whether every contour's fix is settled, how many nodes it added
    (--add-nodes; its move is then from the positions after the split), and whether
    tests/report/exact_glif_check.py (rational arithmetic, independent of
    cmr) passes the written glyph under the same gates;
  - refused: exit 2 with one of the proofs that no move passes
    (report/glyph_joins.hpp, refusal: a line that says so, PROOFS below);
  - neither: exit 2 with any other line (a search that ended without a
    fix: "no certified fix", "no fix passes every check", "the grid
    descent ...").
Prints a Markdown table a font (and the glyphs that are neither, the
fixes not settled or not passed by the exact judge), and writes
OUT_DIR/results.json (per font, per glyph: outcome, seconds, move,
settled, exact). A benchmark, not a test: the times and, where a glyph's
time guard ends its search, the outcomes depend on the machine's load.
"""
import json
import os
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..")
MAKE = os.path.join(ROOT, "tools", "make_test_ufo.py")
EXACT = os.path.join(ROOT, "tests", "report", "exact_glif_check.py")
URW = "/usr/share/fonts/opentype/urw-base35/"
GYRE = "/usr/share/texmf/fonts/opentype/public/tex-gyre/"
FONTS = {
    "DejaVu Sans": "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "Nimbus Sans": URW + "NimbusSans-Regular.otf",
    "Noto Serif": "/usr/share/fonts/truetype/noto/NotoSerif-Regular.ttf",
    "TeX Gyre Heros": GYRE + "texgyreheros-regular.otf",
    "TeX Gyre Termes": GYRE + "texgyretermes-regular.otf",
    "Noto Sans": "/usr/share/fonts/truetype/noto/NotoSans-Regular.ttf",
    "DejaVu Serif": "/usr/share/fonts/truetype/dejavu/DejaVuSerif.ttf",
    "Nimbus Roman": URW + "NimbusRoman-Regular.otf",
    "C059": URW + "C059-Roman.otf",
    "URW Bookman Light": URW + "URWBookman-Light.otf",
    "P052": URW + "P052-Roman.otf",
    "URW Gothic Book": URW + "URWGothic-Book.otf",
}
PROOFS = ("no source point may move", " joins a line to a ", "the extremum gate: the quadratic piece ")
AZ = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"


def option(name, default):
    if name in sys.argv:
        i = sys.argv.index(name)
        value = sys.argv[i + 1]
        del sys.argv[i:i + 2]
        return value
    return default


def glif_name(glyph):
    """The UFO file name of a one-letter glyph (capitals get an underscore)."""
    return glyph + "_.glif" if glyph.isupper() else glyph + ".glif"


def exact_gates(gates):
    """exact_glif_check.py's --gates for `gates` (None: both, its default)."""
    names = gates.split(",")
    extrema = any(n.startswith(("curvature-extrema-at-nodes", "extrema-at-nodes")) for n in names)
    g2 = any(n.startswith("g2-at-smooth-nodes") for n in names)
    return None if extrema and g2 else ("extrema" if extrema else "g2")


def run_font(cmr, name, path, out, gates, work, add_nodes=False):
    ufo = os.path.join(out, name.replace(" ", "_") + ".ufo")
    if not os.path.isdir(ufo):
        subprocess.run([sys.executable, MAKE, path, ufo], check=True, capture_output=True)
    rows = {}
    for g in AZ:
        dest = os.path.join(out, name.replace(" ", "_"), g + ".ufo")
        os.makedirs(os.path.dirname(dest), exist_ok=True)
        shutil.rmtree(dest, ignore_errors=True)
        args = [cmr, "fix", ufo, "--glyph", g, "--require", gates, "--out", dest]
        if work:
            args += ["--work", work]
        if add_nodes:
            args += ["--add-nodes"]
        t = time.perf_counter()
        r = subprocess.run(args, capture_output=True, text=True)
        row = {"seconds": round(time.perf_counter() - t, 3)}
        if r.returncode == 0:
            doc = json.loads(r.stdout)
            contours = doc["contours"]
            if all(c.get("already") for c in contours):
                row["outcome"] = "pass"
            else:
                row["outcome"] = "fixed"
                row["move"] = sum((m["to"][0] - m["from"][0]) ** 2 + (m["to"][1] - m["from"][1]) ** 2
                                  for c in contours for m in c.get("moves", []))
                row["settled"] = all(c.get("settled") or c.get("already") for c in contours)
                row["added"] = sum(len(c.get("added_nodes", [])) for c in contours)
                check = [sys.executable, EXACT, os.path.join(dest, "glyphs", glif_name(g))]
                if exact_gates(gates):
                    check += ["--gates", exact_gates(gates)]
                row["exact"] = subprocess.run(check, capture_output=True).returncode == 0
        else:
            line = r.stderr.strip().splitlines()[0] if r.stderr.strip() else ""
            row["outcome"] = "refused" if any(s in line for s in PROOFS) else "neither"
            row["line"] = line
        rows[g] = row
    return rows


def main():
    gates = option("--gates", "curvature-extrema-at-nodes,g2-at-smooth-nodes")
    work = option("--work", None)
    add_nodes = "--add-nodes" in sys.argv
    if add_nodes:
        sys.argv.remove("--add-nodes")
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    cmr = os.path.abspath(sys.argv[1]) if os.sep in sys.argv[1] else sys.argv[1]
    out = os.path.abspath(sys.argv[2])
    os.makedirs(out, exist_ok=True)
    fonts = {}
    for item in sys.argv[3:] or list(FONTS):
        name, _, path = item.partition("=")
        fonts[name] = path or FONTS[name]
    results = {}
    print(f"gates {gates}; work {work or 'default'}{'; --add-nodes' if add_nodes else ''}; load {os.getloadavg()}")
    print()
    print("| font | fixed | refused with a proof | pass as they are | neither | total move of the fixes (units²) "
          "| worst (s) |" + (" fixed with nodes added (nodes) |" if add_nodes else ""))
    print("|---|---|---|---|---|---|---|" + ("---|" if add_nodes else ""))
    for name, path in fonts.items():
        rows = run_font(cmr, name, path, out, gates, work, add_nodes)
        results[name] = rows
        count = {k: sum(1 for r in rows.values() if r["outcome"] == k) for k in ("fixed", "refused", "pass", "neither")}
        moved = sum(r.get("move", 0) for r in rows.values())
        worst = max(r["seconds"] for r in rows.values())
        neither = " ".join(g for g, r in rows.items() if r["outcome"] == "neither")
        print(f"| {name} | {count['fixed']} | {count['refused']} | {count['pass']} | {count['neither']}"
              f"{' (' + neither + ')' if neither else ''} | {moved:,.0f} | {worst:.1f} |" +
              (f" {sum(1 for r in rows.values() if r.get('added'))} ({sum(r.get('added', 0) for r in rows.values())}) |"
               if add_nodes else ""), flush=True)
    print()
    for name, rows in results.items():
        for g, r in rows.items():
            if r["outcome"] == "fixed" and not r["settled"]:
                print(f"{name} {g}: fixed, not settled")
            if r["outcome"] == "fixed" and not r["exact"]:
                print(f"{name} {g}: FIX NOT PASSED BY THE EXACT JUDGE")
    with open(os.path.join(out, "results.json"), "w") as f:
        json.dump(results, f, indent=1)
    print(f"load {os.getloadavg()}")


if __name__ == "__main__":
    main()
