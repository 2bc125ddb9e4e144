"""Checks of a written-back .glif shared by the font-source tests (ufo_source_test.py, random_glyphs_test.py)."""
import re


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
