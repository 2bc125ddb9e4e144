#!/usr/bin/python3
"""cmr report --shard i/N and --merge (report/merge.hpp), end to end.

A collection (spline files, a folder, a font) is reported whole and in
shards; the shards' splines must be disjoint and together the whole run's,
and merging the shards must give the whole run's findings (as a set),
summary counts, JUnit test cases and SARIF result count. Bad --shard values,
a folder without report.json and parts with different options must each give
one line and exit 2, and leave no output folder behind.

usage: shard_merge_test.py CMR SOURCE_DIR
"""
import json
import os
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET
from collections import Counter

CMR, SRC = sys.argv[1], sys.argv[2]
FONT = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what)


def run(*args):
    return subprocess.run([CMR, "report", *args], capture_output=True, text=True, cwd=SRC)


def one_line_exit_2(r, what):
    lines = [l for l in r.stderr.splitlines() if not l.startswith("note:")]
    check(r.returncode == 2, f"{what}: exit {r.returncode}, not 2 ({r.stderr.strip()})")
    check(len(lines) == 1, f"{what}: {len(lines)} lines on stderr, not one: {r.stderr!r}")


def spline_key(s):
    s = dict(s)
    s.pop("id", None)
    return json.dumps(s, sort_keys=True)


def findings(report):
    return Counter(json.dumps(f, sort_keys=True) for s in report["splines"] for f in s.get("findings", []))


def junit_cases(path):
    root = ET.parse(path).getroot()
    return Counter((c.get("classname"), c.get("name"), c.find("failure") is not None)
                   for c in root.iter("testcase"))


def counts(summary):
    return {k: summary[k] for k in ("splines", "pass", "fail", "invalid", "files", "findings", "exit_code")}


inputs = ["examples/report", "examples/uniform.json", "examples/wave.json", "examples/clamped.json",
          "examples/bezier9.json"]
if os.path.exists(FONT):
    inputs.append(FONT)
gates = ["--require", "cmr,curvature-extrema-at-nodes", "--glyphs", "a-e", "--no-thumbnails", "--quiet"]

with tempfile.TemporaryDirectory() as tmp:
    def out(name, *extra):
        d = os.path.join(tmp, name)
        return ["--out", d, "--junit", d + "/junit.xml", "--sarif", d + "/report.sarif",
                "--markdown", d + "/report.md", *extra]

    whole = run(*inputs, *gates, *out("whole"))
    check(whole.returncode in (0, 1), f"whole run: exit {whole.returncode}: {whole.stderr}")
    W = json.load(open(os.path.join(tmp, "whole", "report.json")))
    N = 3
    parts, seen = [], Counter()
    for i in range(1, N + 1):
        r = run(*inputs, *gates, *out(f"s{i}"), "--shard", f"{i}/{N}", "--jobs", "1")
        check(r.returncode in (0, 1), f"shard {i}/{N}: exit {r.returncode}: {r.stderr}")
        part = json.load(open(os.path.join(tmp, f"s{i}", "report.json")))
        parts.append(part)
        files = {s["file"] for s in part["splines"]}
        for f in files:
            seen[f] += 1
        check(len(part["splines"]) > 0, f"shard {i}/{N} is empty: the test's collection is too small")
    check(all(c == 1 for c in seen.values()), f"an input in two shards: {seen}")
    if os.path.exists(FONT):  # a font's glyphs are items of their own, spread over the shards
        with_font = [p for p in parts if any(s["file"].startswith(FONT) for s in p["splines"])]
        check(len(with_font) == N, f"the font's glyphs are in {len(with_font)} of {N} shards")
    union = Counter(spline_key(s) for p in parts for s in p["splines"])
    check(union == Counter(spline_key(s) for s in W["splines"]),
          "the shards' splines are not the whole run's (as a multiset)")

    merged_dir = os.path.join(tmp, "merged")
    m = run("--merge", *[os.path.join(tmp, f"s{i}") for i in range(1, N + 1)], *out("merged"))
    check(m.returncode == whole.returncode, f"merge exit {m.returncode}, the whole run's {whole.returncode}: {m.stderr}")
    M = json.load(open(os.path.join(merged_dir, "report.json")))
    check(M["schema"] == W["schema"] and M["settings"] == W["settings"], "merged schema/settings differ")
    check(findings(M) == findings(W), "merged findings differ from the whole run's")
    check(counts(M["summary"]) == counts(W["summary"]),
          f"merged summary {counts(M['summary'])} != whole {counts(W['summary'])}")
    check(sorted(s["id"] for s in M["splines"]) == sorted(f"s{k}" for k in range(len(M["splines"]))),
          "merged ids are not s0..s(n-1)")
    check(junit_cases(os.path.join(merged_dir, "junit.xml")) == junit_cases(os.path.join(tmp, "whole", "junit.xml")),
          "merged JUnit test cases differ")
    suites = [s.get("id") for s in ET.parse(os.path.join(merged_dir, "junit.xml")).getroot().iter("testsuite")]
    check(suites == [str(k) for k in range(len(suites))], f"merged JUnit suite ids {suites}")
    res = lambda d: json.load(open(os.path.join(d, "report.sarif")))["runs"][0]["results"]
    check(len(res(merged_dir)) == len(res(os.path.join(tmp, "whole"))), "merged SARIF result count differs")
    for i in range(1, N + 1):
        check(os.path.exists(os.path.join(merged_dir, "parts", f"s{i}", "index.html")), f"part s{i} not copied")
        check(f'href="parts/s{i}/index.html"' in open(os.path.join(merged_dir, "index.html")).read(),
              f"index.html does not link part s{i}")
    check(open(os.path.join(merged_dir, "report.md")).read().startswith("## cmr report"), "merged Markdown heading")

    # --jobs 1 judges as every core does.
    j1 = run(*inputs, *gates, "--out", os.path.join(tmp, "j1"), "--jobs", "1")
    J = json.load(open(os.path.join(tmp, "j1", "report.json")))
    check(Counter(spline_key(s) for s in J["splines"]) == Counter(spline_key(s) for s in W["splines"]),
          "--jobs 1 gives another report")
    check(j1.returncode == whole.returncode, "--jobs 1: another exit code")

    # An unreadable font is one invalid item, in one part only; a font whose
    # glyphs a part does not take is no file of that part's count.
    broken = os.path.join(tmp, "broken.ttf")
    open(broken, "wb").write(b"not a font")
    few = ["examples/uniform.json", broken, FONT, "--glyphs", "a", "--no-thumbnails", "--quiet"]
    wr = run(*few, "--out", os.path.join(tmp, "few"))
    for i in (1, 2, 3):
        run(*few, "--out", os.path.join(tmp, f"few{i}"), "--shard", f"{i}/3")
    fm = run("--merge", *[os.path.join(tmp, f"few{i}") for i in (1, 2, 3)], "--out", os.path.join(tmp, "few-merged"))
    FW = json.load(open(os.path.join(tmp, "few", "report.json")))["summary"]
    FM = json.load(open(os.path.join(tmp, "few-merged", "report.json")))["summary"]
    check(wr.returncode == 2 and fm.returncode == 2, f"broken font: exits {wr.returncode}, merged {fm.returncode}")
    check(counts(FM) == counts(FW), f"broken font: merged {counts(FM)} != whole {counts(FW)}")

    # With a baseline each part compares its findings with the whole
    # baseline; the merge's new / fixed / unchanged are the whole run's.
    base = ["examples/report", "examples/uniform.json", "--require", "cmrwi,curvature-extrema-at-nodes",
            "--no-thumbnails", "--quiet", "--baseline", os.path.join(tmp, "base", "report.json")]
    run("examples/report", "--require", "cmrwi,curvature-extrema-at-nodes", "--no-thumbnails", "--quiet",
        "--out", os.path.join(tmp, "base"))
    bw = run(*base, "--out", os.path.join(tmp, "bw"))
    for i in (1, 2):
        run(*base, "--out", os.path.join(tmp, f"b{i}"), "--shard", f"{i}/2")
    bm = run("--merge", os.path.join(tmp, "b1"), os.path.join(tmp, "b2"), "--out", os.path.join(tmp, "bm"))
    BW = json.load(open(os.path.join(tmp, "bw", "report.json")))["summary"]
    BM = json.load(open(os.path.join(tmp, "bm", "report.json")))["summary"]
    check(bw.returncode == bm.returncode, f"baseline: merged exit {bm.returncode}, whole {bw.returncode}")
    check(counts(BM) == counts(BW) and BM.get("baseline") == BW.get("baseline"),
          f"baseline: merged {BM} != whole {BW}")

    # A designspace under an interpolation gate (tools/make_test_designspace.py's kink family and the same
    # glyph O again as a second designspace: its masters' pieces): each glyph in one shard only, as a font's,
    # and the merge is the whole run. Until 3 Dec every shard judged every glyph (the merge counted each twice).
    dsdir = os.path.join(tmp, "ds")
    subprocess.run(["/usr/bin/python3", os.path.join(SRC, "tools", "make_test_designspace.py"), dsdir], check=True,
                   capture_output=True)
    vin = [os.path.join(dsdir, "kink.designspace"), os.path.join(dsdir, "three.designspace")]
    vgates = ["--require", "g1-between-masters", "--no-thumbnails", "--quiet"]
    vw = run(*vin, *vgates, "--out", os.path.join(tmp, "vwhole"))
    VW = json.load(open(os.path.join(tmp, "vwhole", "report.json")))
    check(vw.returncode == 1 and VW["summary"]["findings"] > 0, f"designspaces at g1-between-masters: {VW['summary']}")
    vparts = []
    for i in (1, 2):
        run(*vin, *vgates, "--shard", f"{i}/2", "--out", os.path.join(tmp, f"v{i}"))
        vparts.append(json.load(open(os.path.join(tmp, f"v{i}", "report.json"))))
    check(Counter(spline_key(s) for p in vparts for s in p["splines"]) == Counter(spline_key(s) for s in VW["splines"]),
          "interpolation shards: not the whole run's splines (as a multiset)")
    vm = run("--merge", os.path.join(tmp, "v1"), os.path.join(tmp, "v2"), "--out", os.path.join(tmp, "vmerged"))
    VM = json.load(open(os.path.join(tmp, "vmerged", "report.json")))
    check(vm.returncode == vw.returncode and findings(VM) == findings(VW) and counts(VM["summary"]) == counts(VW["summary"]),
          f"interpolation merge: exit {vm.returncode}, {counts(VM['summary'])} != whole {counts(VW['summary'])}")

    # Bad input: one line, exit 2, nothing written.
    for bad in ["0/2", "3/2", "1/0", "0/0", "x", "1/x", "1", "-1/2", "1/2/3", ""]:
        d = os.path.join(tmp, "bad-shard")
        r = run(*inputs, *gates, "--out", d, "--shard", bad)
        one_line_exit_2(r, f"--shard {bad!r}")
        check(not os.path.exists(d), f"--shard {bad!r} left {d}")
    os.makedirs(os.path.join(tmp, "empty"))
    for name, parts_ in [("no report.json", ["s1", "empty"]),
                         ("no such folder", ["s1", "nothing-here"]),
                         ("output among the parts", ["s1", "merged-bad"])]:
        d = os.path.join(tmp, "merged-bad")
        r = run("--merge", *[os.path.join(tmp, p) for p in parts_], "--out", d)
        one_line_exit_2(r, f"merge: {name}")
        check(not os.path.exists(d), f"merge: {name}: left {d}")
    other = run(*inputs, "--require", "cmrwi", "--glyphs", "a-e", "--no-thumbnails", "--quiet", "--shard", "2/3",
                "--out", os.path.join(tmp, "other"))
    d = os.path.join(tmp, "merged-bad")
    r = run("--merge", os.path.join(tmp, "s1"), os.path.join(tmp, "other"), "--out", d)
    one_line_exit_2(r, "merge: parts with different --require")
    check(not os.path.exists(d), "merge with different options left its folder")
    r = run("--merge", os.path.join(tmp, "s1"), os.path.join(tmp, "other"), "--out", d, "--junit", d + "/junit.xml")
    one_line_exit_2(r, "merge: a part without the JUnit file asked for")
    r = run("--merge", os.path.join(tmp, "s1"), "examples/uniform.json", "--out", d)
    one_line_exit_2(r, "merge: FILES with --merge")

print("ok" if not failures else f"{len(failures)} failures")
sys.exit(1 if failures else 0)
