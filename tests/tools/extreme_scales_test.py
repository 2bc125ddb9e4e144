#!/usr/bin/python3
"""Curves near the ends of the double range, through the CLI: no crash, the
documented exits, and the same answers as at unit size.

The paper's fig2 and fig8 scaled by 2^600, 2^-600 and 2^1000, each as given
and moved so that its moved point is at the origin; the views: the default,
and one 2^-418 wide around the moved point (where the setup scales by about
2^-600, a block with a pixel column within 8 of the middle cannot be scaled
and the others can: block.cpp once handed such a block's quarters an earlier
block's facts, and crashed). Commands: analyze, fix (cmrwi), report, region
on the CPU and on the Vulkan device (lavapipe; skipped without one); and
fix of Fig. 8 lifted into space at the same scales. Checks:
every run exits 0-3 (no signal: GMP's SIGFPE on an infinite position once
ended fix and report), the CPU and Vulkan label maps are equal, and fig8's
fix is found at every scale, at the same place relative to the curve as at
unit size.

Usage: extreme_scales_test.py CMR SOURCE_DIR WORKDIR
"""
import json
import os
import shutil
import subprocess
import sys

CMR = os.path.abspath(sys.argv[1])
SRC = os.path.abspath(sys.argv[2])
WORK = os.path.abspath(sys.argv[3])
failures = []


def check(ok, what, detail=""):
    """Prints the check; `detail` (a run's stderr) only where it fails."""
    if not ok and detail.strip():
        what += ": " + detail.strip()[-300:]
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def run(args, timeout=300):
    p = subprocess.run([CMR] + args, cwd=WORK, capture_output=True, text=True, timeout=timeout)
    return p.returncode, p.stdout, p.stderr


def scaled(name, point, e, to_origin):
    d = json.load(open(os.path.join(SRC, "examples", "figures", name + ".json")))
    at = d["points"][point] if to_origin else [0.0, 0.0]
    d["points"] = [[(q[0] - at[0]) * 2.0 ** e, (q[1] - at[1]) * 2.0 ** e] for q in d["points"]]
    path = os.path.join(WORK, "%s_%d_%d.json" % (name, e, to_origin))
    with open(path, "w") as f:
        json.dump(d, f)
    return path, d["points"][point]


def vulkan_present():
    code, _, _ = run(["region", os.path.join(SRC, "examples", "figures", "fig2.json"), "--point", "1", "--size",
                      "8x8", "--backend", "vulkan"])
    return code == 0


def main():
    shutil.rmtree(WORK, ignore_errors=True)
    os.makedirs(WORK)
    vulkan = vulkan_present()
    print("Vulkan device:", "yes" if vulkan else "none (the label comparisons are skipped)")
    unit = None
    for name, point in (("fig8", 3), ("fig2", 1)):
        for e in (0, 600, -600, 1000):
            for to_origin in (0, 1):
                if e == 0 and to_origin:
                    continue
                path, at = scaled(name, point, e, to_origin)
                tag = "%s x 2^%d%s" % (name, e, ", moved point at the origin" if to_origin else "")
                code, _, err = run(["analyze", path])
                check(code in (0, 1), "%s: analyze exits %d" % (tag, code), err)
                code, out, err = run(["fix", path, "--require", "cmrwi", "--points", str(point), "--out",
                                      os.path.join(WORK, "fixed.json")])
                check(code in (0, 1, 2), "%s: fix exits %d" % (tag, code), err)
                if name == "fig8" and code == 0:
                    f = json.loads(out)
                    moved = f["moves"][0]
                    relative = moved["distance"] / f["size"]
                    if e == 0:
                        unit = relative
                    # The same fix within the search's tolerance (1e-6 of the size): bit for bit where only
                    # scaled (a power of two), within it where moved to the origin (other roundings).
                    check(f["fixed"] and unit is not None and abs(relative - unit) <= 2e-6,
                          "%s: fix moves P%d %.17g of the curve's size (at unit size %s)" % (tag, point, relative,
                                                                                       unit))
                elif name == "fig8":
                    check(False, "%s: fix finds fig8's fix (exit %d)" % (tag, code), err)
                report = os.path.join(WORK, "report_%s_%d_%d" % (name, e, to_origin))
                code, _, err = run(["report", path, "--out", report, "--quiet", "--require",
                                    "cmr,g2-at-smooth-nodes"])
                check(code in (0, 1), "%s: report exits %d" % (tag, code), err)
                half = 2.0 ** (-419 if e == 600 and to_origin else e - 4)
                for view in ([], ["--view=%r,%r,%r,%r" % (at[0] - half, at[1] - half, at[0] + half, at[1] + half)]):
                    for mode in ("cmrwi", "cmr"):
                        labels = {}
                        for backend in ("cpu", "vulkan") if vulkan else ("cpu",):
                            pgm = os.path.join(WORK, "labels_%s.pgm" % backend)
                            code, _, err = run(["region", path, "--point", str(point), "--size", "96x80", "--depth",
                                                "10", "--mode", mode, "--backend", backend, "--labels", pgm] + view)
                            what = "%s: region %s, %s, %s" % (tag, mode, backend, "zoom" if view else "default view")
                            check(code == 0, "%s exits %d" % (what, code), err)
                            if code == 0:
                                with open(pgm, "rb") as f:
                                    labels[backend] = f.read()
                        if len(labels) == 2:
                            check(labels["cpu"] == labels["vulkan"], "%s: region %s, %s: CPU and Vulkan labels equal"
                                  % (tag, mode, "zoom" if view else "default view"))
    # A space curve (Fig. 8 lifted): its fix at every scale (space_fix scales it too).
    lifted = json.load(open(os.path.join(SRC, "examples", "space", "fig8_lifted.json")))
    unit = None
    for e in (0, 600, -600, 1000):
        d = dict(lifted)
        d["points"] = [[c * 2.0 ** e for c in q] for q in lifted["points"]]
        path = os.path.join(WORK, "lifted_%d.json" % e)
        with open(path, "w") as f:
            json.dump(d, f)
        code, out, err = run(["fix", path, "--require", "cmrwi", "--out", os.path.join(WORK, "fixed3.json")])
        tag = "fig8 lifted x 2^%d" % e
        check(code == 0, "%s: fix exits %d" % (tag, code), err)
        if code == 0:
            f = json.loads(out)
            relative = f["moves"][0]["distance"] / f["size"]
            if e == 0:
                unit = relative
            check(f["fixed"] and abs(relative - unit) <= 1e-12 * unit,
                  "%s: fix moves P%d %.17g of the curve's size (at unit size %s)" % (tag, f["moves"][0]["point"],
                                                                               relative, unit))
    if failures:
        print("%d failed:" % len(failures))
        for f in failures:
            print("  " + f)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
