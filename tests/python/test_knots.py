"""cmr.knots.*, cmr.kcurve and cmr.report equal `cmr knots`, `cmr kcurve` and `cmr report`."""

import json
import os

import numpy as np
import pytest

import cmr
from conftest import ROOT, cli_json, run_cmr


@pytest.mark.parametrize("op,args,call", [
    ("insert", ["2.5"], lambda s: cmr.knots.insert(s, 2.5)),
    ("insert", ["3.25", "--times", "2"], lambda s: cmr.knots.insert(s, 3.25, times=2)),
    ("refine", [], cmr.knots.refine),
    ("elevate", [], cmr.knots.elevate),
    ("clamp", [], cmr.knots.clamp),
    ("uniform", [], cmr.knots.uniform),
    ("set", ["4", "3.5"], lambda s: cmr.knots.set(s, 4, 3.5)),
])
def test_knot_operation_equals_cli(fig8_path, op, args, call):
    assert call(cmr.Spline.load(str(fig8_path))).to_dict() == cli_json("knots", fig8_path, op, *args)


def test_remove_undoes_insert(tmp_path, fig8_path):
    s = cmr.Spline.load(str(fig8_path))
    inserted = cmr.knots.insert(s, 3.5)
    path = tmp_path / "inserted.json"
    path.write_text(json.dumps(inserted.to_dict()))
    removed = cmr.knots.remove(inserted, 3.5)
    assert removed.to_dict() == cli_json("knots", path, "remove", "3.5")
    assert np.allclose(removed.points, s.points, atol=1e-12)


def test_kcurve_equals_cli(tmp_path):
    for path in sorted((ROOT / "examples" / "kcurve").glob("*.json")):
        doc = json.loads(path.read_text())
        if set(doc) - {"points", "closed"}:
            continue
        spline = cmr.kcurve(np.array(doc["points"], dtype=float), closed=doc.get("closed", False))
        assert spline.to_dict() == cli_json("kcurve", path), path.name
        cubic = cmr.kcurve(doc["points"], closed=doc.get("closed", False), cubic=True)
        assert cubic.to_dict() == cli_json("kcurve", path, "--cubic"), path.name


def test_report_equals_cli(tmp_path):
    # cmr.report runs the command's batch: the same exit code, the same
    # one-line summary counts and the same report.json entries.
    files = [str(p) for p in sorted((ROOT / "examples" / "report").glob("*.json"))] + [str(ROOT / "examples/wave.json")]
    out = tmp_path / "cli"
    p = run_cmr("report", *files, "--require", "cmrwi", "--no-thumbnails", "--quiet", "--out", out, check=False)
    cli = json.loads((out / "report.json").read_text())
    r = cmr.report(files, require="cmrwi", thumbnails=False)
    assert r["exit_code"] == p.returncode and r["out"] is None
    assert r["summary"].split(";")[0] == p.stdout.split(";")[0]
    assert [(s["name"], s["status"], s["verdict"]) for s in r["report"]["splines"]] == \
        [(s["name"], s["status"], s["verdict"]) for s in cli["splines"]]
    kept = cmr.report(files, require="cmrwi", thumbnails=False, out=tmp_path / "py")
    assert kept["out"] == str(tmp_path / "py") and (tmp_path / "py" / "index.html").exists()


INTER = "/usr/share/fonts/truetype/inter-vf/Inter-roman.var.ttf"  # Debian fonts-inter-variable (tools/setup.sh)


def test_report_of_a_variable_fonts_instance_equals_cli(tmp_path):
    # location= is --location: the instance judged, named in the settings;
    # two instances give different curves, and the CLI's report is the same.
    assert os.path.exists(INTER), "tools/setup.sh installs fonts-inter-variable"
    gate = "curvature-extrema-at-nodes"
    thin = cmr.report(INTER, glyphs="O,S", require=gate, location="wght=100", thumbnails=False, fixes=False)
    black = cmr.report(INTER, glyphs="O,S", require=gate, location={"wght": 900}, thumbnails=False, fixes=False)
    default = cmr.report(INTER, glyphs="O,S", require=gate, thumbnails=False, fixes=False)
    assert thin["report"]["settings"]["location"] == {"wght": 100}
    assert black["report"]["settings"]["location"] == {"wght": 900}
    assert "location" not in default["report"]["settings"]
    curves = [[s["curvature"] for s in r["report"]["splines"]] for r in (thin, black, default)]
    assert curves[0] != curves[1] and curves[1] != curves[2] and curves[0] != curves[2]
    out = tmp_path / "cli"
    p = run_cmr("report", INTER, "--glyphs", "O,S", "--require", gate, "--location", "wght=900", "--no-thumbnails",
                "--no-fixes", "--quiet", "--out", out, check=False)
    cli = json.loads((out / "report.json").read_text())
    assert black["exit_code"] == p.returncode and black["report"]["settings"] == cli["settings"]
    assert [(s["name"], s["curvature"], s.get("gates")) for s in black["report"]["splines"]] == \
        [(s["name"], s["curvature"], s.get("gates")) for s in cli["splines"]]
    # outside the axis: the font is invalid (exit 2, one message); not a font, or not TAG=VALUE: InputError
    far = cmr.report(INTER, glyphs="O", location="wght=2000", thumbnails=False)
    assert far["exit_code"] == 2 and len(far["invalid"]) == 1 and "outside the axis's range" in far["invalid"][0]
    with pytest.raises(cmr.InputError, match="location: for variable fonts"):
        cmr.report(str(ROOT / "examples" / "wave.json"), location="wght=700")
    with pytest.raises(cmr.InputError, match="is not TAG=VALUE"):
        cmr.report(INTER, location="wght")


def test_report_of_a_font_source_judges_severity_as_the_cli(tmp_path):
    # A font's findings get their severity by default, as the command's: under
    # g2 alone Nimbus Sans e and r have only jumps that a move below half a
    # unit removes (info), so they pass and o fails; strict=True,
    # severity=False and a small min_severity fail e and r too, as --strict,
    # --no-severity and --min-severity do.
    import subprocess
    import sys
    ufo = tmp_path / "N.ufo"
    subprocess.run([sys.executable, str(ROOT / "tools" / "make_test_ufo.py"),
                    "/usr/share/fonts/opentype/urw-base35/NimbusSans-Regular.otf", str(ufo), "ero"], check=True)
    for kwargs, flags in (({}, []), ({"strict": True}, ["--strict"]), ({"severity": False}, ["--no-severity"]),
                          ({"min_severity": 0.001}, ["--min-severity", "0.001"])):
        r = cmr.report(ufo, glyphs="all", require="g2-at-smooth-nodes", thumbnails=False, fixes=False, **kwargs)
        out = tmp_path / ("cli" + "".join(flags).replace("-", "").replace(".", ""))
        p = run_cmr("report", ufo, "--glyphs", "all", "--require", "g2-at-smooth-nodes", *flags, "--no-thumbnails",
                    "--no-fixes", "--quiet", "--out", out, check=False)
        cli = json.loads((out / "report.json").read_text())
        assert r["exit_code"] == p.returncode == 1 and r["report"]["settings"] == cli["settings"]
        assert [(s["name"], s["status"], s.get("findings")) for s in r["report"]["splines"]] == \
            [(s["name"], s["status"], s.get("findings")) for s in cli["splines"]]
        failing = sorted({s["glyph"] for s in r["report"]["splines"] if s["status"] == "fail"})
        assert failing == (["o"] if kwargs == {} else ["e", "o", "r"]), (kwargs, failing)
    with pytest.raises(cmr.InputError, match="severity=False: not with min_severity"):
        cmr.report(ufo, severity=False, min_severity=1)
    with pytest.raises(cmr.InputError, match="strict: not with severity=False"):
        cmr.report(ufo, severity=False, strict=True)


def test_report_of_a_designspace_with_interpolation_gates_equals_cli(tmp_path):
    # With an interpolation gate a designspace is one file, its masters judged
    # together (it had been walked into its two UFOs, each invalid: "one
    # master"); between= is --between.
    import subprocess
    import sys
    subprocess.run([sys.executable, str(ROOT / "tools" / "make_test_designspace.py"), str(tmp_path)], check=True,
                   capture_output=True)
    ds = str(tmp_path / "kink.designspace")
    for kwargs, flags in (({}, []), ({"between": "wght=400:wght=500"}, ["--between", "wght=400:wght=500"])):
        r = cmr.report(ds, require="g1-between-masters", thumbnails=False, fixes=False, **kwargs)
        out = tmp_path / ("cli" + str(len(flags)))
        p = run_cmr("report", ds, "--require", "g1-between-masters", *flags, "--no-thumbnails", "--no-fixes", "--quiet",
                    "--out", out, check=False)
        cli = json.loads((out / "report.json").read_text())
        assert r["exit_code"] == p.returncode == 1 and r["invalid"] == [] and r["items"] == 1
        assert [(s["name"], s["status"], s.get("findings")) for s in r["report"]["splines"]] == \
            [(s["name"], s["status"], s.get("findings")) for s in cli["splines"]]
    with pytest.raises(cmr.InputError, match="between: only with an interpolation gate"):
        cmr.report(ds, between="wght=400:wght=500")


def test_report_of_every_glyph_of_a_font_source(tmp_path):
    # glyphs="all" is --glyphs all: every glyph of a UFO, whatever its code points.
    ufo = str(ROOT / "examples" / "ufo" / "Sans.ufo")
    every = cmr.report(ufo, glyphs="all", thumbnails=False, fixes=False)
    p = run_cmr("report", ufo, "--glyphs", "all", "--no-thumbnails", "--no-fixes", "--quiet", "--out",
                tmp_path / "cli", check=False)
    assert every["summary"].split(";")[0] == p.stdout.split(";")[0] and every["items"] > 0


def test_report_cache_is_written_unless_turned_off(tmp_path):
    # A font's report keeps its resume cache (report.cache) in `out`, as the
    # command does; cache=False is --no-cache: none is read or written.
    ufo = str(ROOT / "examples" / "ufo" / "Sans.ufo")
    kept = cmr.report(ufo, require="curvature-extrema-at-nodes", thumbnails=False, fixes=False, out=tmp_path / "a")
    assert (tmp_path / "a" / "report.cache").is_file()
    off = cmr.report(ufo, require="curvature-extrema-at-nodes", thumbnails=False, fixes=False, out=tmp_path / "b",
                     cache=False)
    assert not (tmp_path / "b" / "report.cache").exists()
    assert off["exit_code"] == kept["exit_code"] and off["report"]["splines"] == kept["report"]["splines"]
    with pytest.raises(cmr.InputError, match="unknown option 'cache_dir'"):
        cmr.report(ufo, cache_dir="x")
