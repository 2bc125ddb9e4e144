"""Checks shared by the font-source tests (ufo_source_test.py, random_glyphs_test.py,
add_nodes_test.py): of a written-back .glif, and a script's PASS/FAIL tally."""
import re
import sys


def only_xy_changed(a, b):
    """Every line the same but for x/y values of <point>s; new values integers."""
    la, lb = open(a).read().split("\n"), open(b).read().split("\n")
    if len(la) != len(lb):
        return False, "line count differs"
    changed = 0
    for x, y in zip(la, lb):
        if x == y:
            continue
        changed += 1
        strip = lambda s: re.sub(r'\b([xy])="[^"]*"', r'\1=""', s)
        if "<point" not in x or strip(x) != strip(y):
            return False, "a line other than x/y changed: " + y
        for v in re.findall(r'\b[xy]="([^"]*)"', y):
            if not re.fullmatch(r"-?\d+", v):
                return False, "not an integer coordinate: " + v
    return changed > 0, "%d lines changed" % changed


class Checks:
    """A test script's checks: one PASS or FAIL line each, and the tally at the end."""

    def __init__(self):
        self.results = []

    def __call__(self, name, ok, detail=""):
        self.results.append(bool(ok))
        print(("PASS " if ok else "FAIL ") + name + ("" if ok else ": " + str(detail)[:600]))

    def exit(self):
        """Prints "N passed, M failed" and exits 1 on any failure."""
        print("%d passed, %d failed" % (self.results.count(True), self.results.count(False)))
        sys.exit(0 if all(self.results) else 1)
