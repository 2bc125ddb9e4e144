#!/usr/bin/python3
"""Work and memory of `cmr report` bounded by the input (issue 42 item 7).

Each reproducer of the review is generated here (no big committed files)
and run under a memory ceiling (RLIMIT_AS, as `ulimit -v`) and a wall-clock
limit:

- an SVG of 10^5 paths: reports under 500 MB of address space and within
  the time below (its splines are reported and written 1,024 at a time, so
  memory does not grow with the paths of one file; the fix searches stop
  at --fix-budget);
- a glyph of 4,000 contours and a glyph of one 32,000-point contour, with
  region thumbnails on: bounded by the fix budget (a spline of more than
  512 control points gets no region fix search);
- --time-limit: a run past it exits 2 with one line and writes nothing;
- a file written in parts is one file: one JUnit suite with every spline,
  ids numbered in order, the summary counting them all.

Usage: report_limits_test.py CMR WORKDIR
"""
import json
import math
import os
import resource
import shutil
import subprocess
import sys
import time

CMR = os.path.abspath(sys.argv[1])
WORK = sys.argv[2]
MB = 1024 * 1024
if os.environ.get("CMR_SANITIZER_BUILD") == "1":
    # Every check here runs cmr under RLIMIT_AS (ulimit -v), and an ASan
    # program cannot start under one: it reserves terabytes of shadow address
    # space. The Release suite (CI) runs these checks.
    print("skipped in a sanitizer build: ASan cannot run under ulimit -v")
    sys.exit(77)
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def run(args, limit_mb, timeout):
    """Runs cmr ARGS under RLIMIT_AS = limit_mb; (rc, stderr, seconds, its peak RSS in MB); rc None: timed out."""
    def limits():
        resource.setrlimit(resource.RLIMIT_AS, (limit_mb * MB, limit_mb * MB))
    t0 = time.monotonic()
    with open(os.path.join(WORK, "stderr.txt"), "w+b") as err:
        p = subprocess.Popen([CMR] + args, stdout=subprocess.DEVNULL, stderr=err, preexec_fn=limits, cwd=WORK)
        while True:  # wait4: this child's own peak resident size
            pid, status, usage = os.wait4(p.pid, os.WNOHANG)
            if pid != 0:
                break
            if time.monotonic() - t0 > timeout:
                p.kill()
                os.wait4(p.pid, 0)
                err.seek(0)
                return None, err.read().decode(errors="replace"), time.monotonic() - t0, 0
            time.sleep(0.05)
        p.returncode = os.waitstatus_to_exitcode(status)
        err.seek(0)
        text = err.read().decode(errors="replace")
    return p.returncode, text, time.monotonic() - t0, usage.ru_maxrss / 1024


def svg(path, n):
    with open(path, "w") as f:
        f.write('<svg xmlns="http://www.w3.org/2000/svg">\n')
        for i in range(n):  # cubic S-curves: each fails CMR (an inflection), so each would get a fix search
            x, y = (i % 300) * 10, (i // 300) * 10
            f.write(f'<path d="M{x} {y} C{x + 3} {y + 5} {x + 6} {y - 2} {x + 9} {y + 4}"/>\n')
        f.write("</svg>\n")


def glif(path, contours):
    lines = ['<?xml version="1.0" encoding="UTF-8"?>', '<glyph name="A" format="2">', '<advance width="1000"/>',
             '<unicode hex="0041"/>', "<outline>"]
    for c in contours:
        lines.append("<contour>")
        for x, y, t in c:
            lines.append('<point x="%d" y="%d"%s/>' % (x, y, ' type="%s"' % t if t else ""))
        lines.append("</contour>")
    lines += ["</outline>", "</glyph>"]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def wobbly(cx, cy, r, pieces, amp):
    pts = []
    for j in range(pieces):
        a = 2 * math.pi * j / pieces
        d = 2 * math.pi / pieces / 3
        rr = r + amp * math.sin(37 * a)
        pts.append((round(cx + rr * math.cos(a)), round(cy + rr * math.sin(a)), "curve"))
        pts.append((round(cx + (rr + amp / 8) * math.cos(a + d)), round(cy + (rr + amp / 8) * math.sin(a + d)), None))
        pts.append((round(cx + (rr - amp / 8) * math.cos(a + 2 * d)), round(cy + (rr - amp / 8) * math.sin(a + 2 * d)), None))
    return pts


shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)

# 1. A file written in parts is one file.
svg(os.path.join(WORK, "three.svg"), 2500)
rc, err, s, _ = run(["report", "three.svg", "--out", "three", "--junit", "three.xml", "--no-thumbnails"], 2000, 300)
check(rc == 0, f"2,500-path SVG (three parts): exit 0 (got {rc}: {err.strip()[:200]})")
if rc == 0:
    d = json.load(open(os.path.join(WORK, "three", "report.json")))
    ids = [sp["id"] for sp in d["splines"]]
    check(ids == ["s%d" % i for i in range(2500)], "report.json: 2,500 splines, ids s0..s2499 in order")
    names = [sp["name"] for sp in d["splines"]]
    check(names == ["three/path%d/s0" % i for i in range(2500)], "report.json: the paths in the file's order")
    check(d["summary"]["splines"] == 2500 and d["summary"]["files"] == 1, "summary: 1 file, 2,500 splines")
    junit = open(os.path.join(WORK, "three.xml")).read()
    check(junit.count("<testsuite ") == 1 and 'tests="2500"' in junit and junit.count("<testcase ") == 2500,
          "JUnit: one suite for the file with its 2,500 test cases")
    page = open(os.path.join(WORK, "three", "index.html")).read()
    check(page.count('<section') >= 2500 or page.count('id="s2499"') == 1, "index.html: every spline's section")

# 2. --time-limit: past it, exit 2, one line, nothing written.
rc, err, s, _ = run(["report", "three.svg", "--out", "late", "--no-thumbnails", "--time-limit", "0.000001"], 2000, 300)
lines = [l for l in err.splitlines() if l.strip()]
check(rc == 2 and len(lines) == 1 and "--time-limit" in lines[0], f"--time-limit: exit 2 and one line (got {rc}: {lines})")
check(not os.path.exists(os.path.join(WORK, "late")), "--time-limit: nothing written")

# 3. Glyphs of 4,000 contours and of 32,000 points, thumbnails on: bounded by the fix budget.
glif(os.path.join(WORK, "c4000.glif"), [wobbly((k % 64) * 40, (k // 64) * 40, 15, 4, 3) for k in range(4000)])
glif(os.path.join(WORK, "p32000.glif"), [wobbly(0, 0, 10000, 32000 // 3, 300)])
for name, budget, limit in (("c4000", 5, 120), ("p32000", 5, 120)):
    rc, err, s, peak = run(["report", name + ".glif", "--out", name, "--fix-budget", str(budget)], 1000, 600)
    check(rc in (0, 1) and s < limit,
          f"{name}.glif with thumbnails, --fix-budget {budget}: done in {s:.1f} s (< {limit} s) under 1 GB (exit {rc})")
    check("cmr: note:" in err, f"{name}: a note says what the budget left out ({err.strip()[-160:]})")

# 4. An SVG of 10^5 paths: under 500 MB, within 120 s on the loaded 2-core VM (60 s when idle).
svg(os.path.join(WORK, "big.svg"), 100000)
rc, err, s, peak = run(["report", "big.svg", "--out", "big", "--fix-budget", "10"], 500, 300)
check(rc == 0 and s < 120, f"10^5-path SVG: exit 0 in {s:.1f} s (< 120 s) under ulimit -v 500 MB (got {rc}: {err.strip()[-200:]})")
check(peak < 500, f"10^5-path SVG: peak resident {peak:.0f} MB < 500 MB")
if rc == 0:
    with open(os.path.join(WORK, "big", "report.json")) as f:
        f.seek(0, 2)
        f.seek(f.tell() - 400)
        tail = f.read()
    check('"splines":100000' in tail, "10^5-path SVG: the summary counts 100,000 splines")

print(f"{len(failures)} failed")
sys.exit(1 if failures else 0)
