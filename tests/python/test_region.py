"""cmr.region equals `cmr region --labels` (the PGM's bytes as a uint8
(height, width) array), and region_result's counts and areas equal the
command's JSON."""

import numpy as np
import pytest

import cmr
from conftest import ROOT, cli_json, read_pgm, run_cmr

CASES = [
    # file, point, size, view, extra options (CLI flags and Python keywords)
    ("examples/figures/fig8.json", 3, (64, 48), (-0.1, -5.4, 3.0, -2.3), [], {}),
    ("examples/figures/fig8.json", 2, (40, 40), None, ["--mode", "cmr"], {"mode": "cmr"}),
    ("examples/figures/fig10b.json", 3, (50, 30), None, ["--split", "2"], {"split": 2}),
    ("examples/wave.json", 3, (48, 36), (-0.5, -2.6, 6.7, 2.8), ["--split", "2,3"], {"split": [2, 3]}),
    ("examples/wave.json", 2, (32, 32), None, ["--each-piece"], {"each_piece": True}),
    ("examples/rational/nurbs_cubic.json", 5, (66, 34), None, [], {}),
]


@pytest.mark.parametrize("file,point,size,view,flags,options", CASES,
                         ids=[f"{c[0].split('/')[-1]}-P{c[1]}-{'-'.join(c[4]) or 'plain'}" for c in CASES])
def test_labels_equal_pgm(tmp_path, file, point, size, view, flags, options):
    pgm = tmp_path / "labels.pgm"
    args = ["region", ROOT / file, "--point", point, "--size", f"{size[0]}x{size[1]}", "--backend", "cpu",
            "--labels", pgm, *flags]
    if view:
        args += ["--view=" + ",".join(repr(v) for v in view)]
    summary = cli_json(*args)
    width, height, _, pixels = read_pgm(pgm)
    labels = cmr.region(ROOT / file, point=point, size=size, view=view, backend="cpu", **options)
    assert labels.dtype == np.uint8 and labels.shape == (height, width) == (size[1], size[0])
    expected = np.frombuffer(pixels, dtype=np.uint8).reshape(height, width)
    assert len(np.unique(expected)) >= 2, "a one-label map would prove little"
    diff = np.argwhere(labels != expected)
    assert diff.size == 0, f"{len(diff)} pixels differ, first (row, column) {diff[0].tolist()}"
    result = cmr.region_result(ROOT / file, point=point, size=size, view=view, backend="cpu", **options)
    assert np.array_equal(result["labels"], labels)
    assert result["counts"] == summary["points"][0]["counts"]
    assert result["summary"]["view"] == summary["view"]
    for key in ("width", "height", "mode", "backend"):
        assert result["summary"][key] == summary[key], key


def test_contour_areas_equal_cli(tmp_path):
    fig8 = ROOT / "examples/figures/fig8.json"
    summary = cli_json("region", fig8, "--point", 3, "--backend", "cpu", "--size", "40x40",
                       "--view=-0.1,-5.4,3.0,-2.3", "--contours", tmp_path / "c.svg")
    r = cmr.region_result(fig8, point=3, backend="cpu", size=(40, 40), view=(-0.1, -5.4, 3.0, -2.3), contours=True,
                          depth_map=True)
    assert r["areas"] == summary["points"][0]["areas"]
    assert r["depth"].shape == (40, 40) and r["depth"].dtype == np.uint8
    # Each label's outlines: (n, 2) arrays whose shoelace sum is its area.
    for name, loops in r["contours"].items():
        area = sum(0.5 * float(np.sum(l[:, 0] * np.roll(l[:, 1], -1) - np.roll(l[:, 0], -1) * l[:, 1])) for l in loops)
        assert area == pytest.approx(r["areas"][name], rel=1e-9, abs=1e-12), name


def test_depth_map_equals_cli(tmp_path):
    fig8 = ROOT / "examples/figures/fig8.json"
    run_cmr("region", fig8, "--point", 3, "--backend", "cpu", "--size", "30x20", "--depth-map", tmp_path / "d.pgm")
    w, h, _, pixels = read_pgm(tmp_path / "d.pgm")
    r = cmr.region_result(fig8, point=3, backend="cpu", size=(30, 20), depth_map=True)
    assert np.array_equal(r["depth"], np.frombuffer(pixels, dtype=np.uint8).reshape(h, w))


def test_empty_region_note():
    # P0 of Fig. 8 acts on segment 0 only: a view far away gives no region and a note.
    with pytest.warns(cmr.Note):
        labels = cmr.region(ROOT / "examples/figures/fig8.json", point=3, size=(8, 8),
                            view=(100, 100, 101, 101), backend="cpu")
    assert labels.shape == (8, 8)


@pytest.mark.parametrize("plane,flags", [(None, []), ("xy", ["--plane", "xy"]),
                                         ((2.15, -1.31, 0.8, 1, 0, 0, 0, 0.6, 0.8), ["--plane", "2.15,-1.31,0.8,1,0,0,0,0.6,0.8"])],
                         ids=["default-plane", "xy", "nine-numbers"])
def test_space_curve_labels_equal_pgm(tmp_path, plane, flags):
    path = ROOT / "examples/space/fig8_lifted.json"
    pgm = tmp_path / "space.pgm"
    summary = cli_json("region", path, "--point", 2, "--size", "48x40", "--backend", "cpu", "--labels", pgm, *flags)
    w, h, _, pixels = read_pgm(pgm)
    expected = np.frombuffer(pixels, dtype=np.uint8).reshape(h, w)
    assert len(np.unique(expected)) >= 2, "a one-label map would prove little"
    r = cmr.region_result(path, point=2, size=(48, 40), backend="cpu", plane=plane)
    assert r["labels"].shape == (40, 48) and np.array_equal(r["labels"], expected)
    assert r["counts"] == summary["counts"] and r["summary"]["plane"] == summary["plane"]
    assert np.array_equal(cmr.region(path, point=2, size=(48, 40), backend="cpu", plane=plane), expected)


def test_vulkan_backend_equals_cpu_and_environment_errors():
    # On lavapipe where there is no GPU (as tests/vk): the same labels as the CPU backend.
    fig8 = ROOT / "examples/figures/fig8.json"
    cpu = cmr.region(fig8, point=3, size=(64, 48), backend="cpu")
    vk = cmr.region_result(fig8, point=3, size=(64, 48), backend="vulkan")
    assert vk["summary"]["backend"] == "vulkan"
    assert np.array_equal(vk["labels"], cpu)
    # No such device: cmr.EnvironmentError (an OSError) with the command's line (exit 3),
    # except that the library names the option by its field (backend), the command by its flag.
    p = run_cmr("region", fig8, "--point", 3, "--size", "8x8", "--backend", "vulkan", "--device", "no-such-gpu",
                check=False)
    assert p.returncode == 3
    with pytest.raises(cmr.EnvironmentError) as e:
        cmr.region(fig8, point=3, size=(8, 8), backend="vulkan", device="no-such-gpu")
    assert str(e.value).endswith("; or use backend cpu")
    assert isinstance(e.value, OSError) and p.stderr.strip() == "cmr: " + str(e.value).replace(
        "; or use backend cpu", "; or use --backend cpu")
