"""Option checks of the Python API: one clear line per bad option, raised as
cmr.InputError, before anything reaches the C++ library (which checks the
rest with the command's own messages)."""

import math
import numbers
import os

from ._cmr import InputError, Spline, kMaxDegree as MAX_DEGREE, kMaxDepth as MAX_DEPTH, kMaxImageSize as MAX_IMAGE_SIZE


def unknown(function, options, allowed):
    """Refuses keyword options `function` does not take."""
    if options:
        name = sorted(options)[0]
        raise InputError(f"{function}: unknown option '{name}' (options: {', '.join(allowed)})")


def _type(value):
    return type(value).__name__


def integer(name, value, lo=None, hi=None):
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise InputError(f"{name}: expected an integer, got {_type(value)} {value!r}")
    value = int(value)
    if (lo is not None and value < lo) or (hi is not None and value > hi):
        raise InputError(f"{name}: {value} is outside {lo}..{hi}")
    return value


def number(name, value, lo=None, finite=True):
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise InputError(f"{name}: expected a number, got {_type(value)} {value!r}")
    value = float(value)
    if finite and not math.isfinite(value):
        raise InputError(f"{name}: {value} is not a finite number")
    if lo is not None and not value >= lo:
        raise InputError(f"{name}: {value} is below {lo}")
    return value


def choice(name, value, choices):
    if not isinstance(value, str) or value not in choices:
        raise InputError(f"{name}: {value!r} is not one of {', '.join(choices)}")
    return value


def text(name, value):
    if not isinstance(value, str):
        raise InputError(f"{name}: expected a string, got {_type(value)} {value!r}")
    return value


def joints(name, value):
    """split=S, split=[S1, S2, ...] or split="S1,S2": a list of joints."""
    if value is None:
        return []
    if isinstance(value, str):
        parts = [p for p in value.split(",")]
        try:
            return [int(p) for p in parts]
        except ValueError:
            raise InputError(f"{name}: expected joints S1,S2,... (got {value!r})") from None
    if isinstance(value, (list, tuple)):
        return [integer(f"{name}[{i}]", v, 0) for i, v in enumerate(value)]
    return [integer(name, value, 0)]


def segment_range(value):
    """segments=A, segments=(A, B) or segments="A..B": the text parse_segment_range reads."""
    if value is None:
        return None
    if isinstance(value, str):
        return value
    if isinstance(value, (list, tuple)):
        if len(value) != 2:
            raise InputError(f"segments: expected (A, B), got {len(value)} values")
        a, b = (integer("segments", v, 0) for v in value)
        return f"{a}..{b}"
    return str(integer("segments", value, 0))


def each_piece(value):
    """each_piece=None/False (off), True (every joint) or [S1, S2, ...]: (on, joints text)."""
    if value is None or value is False:
        return False, ""
    if value is True:
        return True, ""
    return True, ",".join(str(j) for j in joints("each_piece", value))


def points_list(name, value):
    """points=[K, ...] or "P1,P3": indices."""
    if value is None:
        return []
    if isinstance(value, str):
        out = []
        for item in value.split(","):
            item = item.strip()
            digits = item[1:] if item[:1] in ("P", "p") else item
            if not digits.isdigit():
                raise InputError(f"{name}: expected point indices K,K2,... or P1,P3 (got {value!r})")
            out.append(int(digits))
        return out
    if isinstance(value, (list, tuple)):
        return [integer(f"{name}[{i}]", v, 0) for i, v in enumerate(value)]
    return [integer(name, value, 0)]


def spline(value, function):
    """A cmr.Spline, a spline-file dict or a path to a spline file."""
    if isinstance(value, Spline):
        return value
    if isinstance(value, dict):
        return Spline.from_dict(value)
    if isinstance(value, (str, os.PathLike)):
        return Spline.load(os.fspath(value))
    raise InputError(f"{function}: expected a cmr.Spline, a spline-file dict or a file path, got {_type(value)}")


def size(value):
    if (not isinstance(value, (list, tuple))) or len(value) != 2:
        raise InputError(f"size: expected (width, height), got {value!r}")
    return (integer("size[0]", value[0], 1, MAX_IMAGE_SIZE), integer("size[1]", value[1], 1, MAX_IMAGE_SIZE))


def view(value):
    if value is None:
        return None
    if (not isinstance(value, (list, tuple))) or len(value) != 4:
        raise InputError(f"view: expected (x0, y0, x1, y1), got {value!r}")
    return [number(f"view[{i}]", v) for i, v in enumerate(value)]
