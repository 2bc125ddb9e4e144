#!/usr/bin/python3
"""Compares the findings of two report.json files (before / after a change
that must not change any verdict or severity: docs/report.md "Severity").

    compare_findings.py BEFORE/report.json AFTER/report.json

Each finding is matched by its key (FILE|GLYPH|cC|NODE|GATE, counted: equal
keys in order) and compared by its severity (exactly, as written: the JSON
number's repr), level and severity_note, and each spline by its status.
Prints a summary line and up to 20 differences; exit 0 when they are
identical, 1 otherwise.
"""
import collections
import json
import sys


def load(path):
    doc = json.load(open(path))
    findings = collections.defaultdict(list)
    status = {}
    for sp in doc["splines"]:
        status[(sp.get("source", sp.get("file")), sp.get("glyph"), sp.get("contour"), sp.get("id"))] = sp.get("status")
        for f in sp.get("findings", []):
            findings[f["key"]].append((repr(f.get("severity", "-")), f.get("level", "error"), f.get("severity_note", "")))
    return findings, status


def main():
    (fa, sa), (fb, sb) = load(sys.argv[1]), load(sys.argv[2])
    diffs = []
    for key in sorted(set(fa) | set(fb)):
        a, b = fa.get(key, []), fb.get(key, [])
        if a != b:
            diffs.append("%s: %s -> %s" % (key, a, b))
    for key in sorted(set(sa) | set(sb), key=str):
        if sa.get(key) != sb.get(key):
            diffs.append("status %s: %s -> %s" % (key, sa.get(key), sb.get(key)))
    n = sum(len(v) for v in fa.values())
    print("%d findings before, %d after, %d splines; %d differences" % (n, sum(len(v) for v in fb.values()), len(sa), len(diffs)))
    for d in diffs[:20]:
        print("  " + d)
    sys.exit(1 if diffs else 0)


if __name__ == "__main__":
    main()
