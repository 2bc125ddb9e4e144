"""Shared pieces of the Python module's tests (tests/python, run by ctest as
python.pytest with PYTHONPATH=build/python; docs/python.md)."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
# The cmr program of the same build (ctest sets CMR_EXE); else build/tools/cmr.
CMR = os.environ.get("CMR_EXE") or str(ROOT / "build" / "tools" / "cmr")

import cmr  # noqa: E402  (after the path set-up above)


def run_cmr(*args, check=True):
    """Runs the cmr program; returns its CompletedProcess (text)."""
    p = subprocess.run([CMR, *map(str, args)], capture_output=True, text=True, cwd=ROOT)
    if check and p.returncode != 0:
        raise AssertionError(f"cmr {' '.join(map(str, args))} exited {p.returncode}: {p.stderr.strip()}")
    return p


def cli_json(*args):
    """The JSON the cmr program prints on stdout."""
    return json.loads(run_cmr(*args).stdout)


def read_pgm(path):
    """An 8-bit binary PGM (P5) as (width, height, maxval, bytes)."""
    data = Path(path).read_bytes()
    fields, pos = [], 0
    while len(fields) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        start = pos
        while not data[pos:pos + 1].isspace():
            pos += 1
        fields.append(data[start:pos])
    assert fields[0] == b"P5", fields
    width, height, maxval = (int(f) for f in fields[1:])
    pixels = data[pos + 1:]
    assert len(pixels) == width * height, (len(pixels), width, height)
    return width, height, maxval, pixels


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture
def fig8_path():
    return ROOT / "examples" / "figures" / "fig8.json"


@pytest.fixture
def fig8():
    return cmr.Spline.load(str(ROOT / "examples" / "figures" / "fig8.json"))


def pytest_report_header(config):
    return [f"cmr module: {cmr.__file__}", f"cmr program: {CMR}", f"python: {sys.executable}"]
