#!/usr/bin/python3
"""Concurrent runs into one output folder (issue 42 item 6).

An owned output folder (`report --out`, `import --out`, `sweep --out-dir`)
is committed under its lock; a run into which another run committed while
it ran writes nothing and says so in one line (exit 3). Checked here:

- a long report, and a short report started while it runs, into the same
  --out: the short one commits; the long one exits 3 with the one line; the
  folder holds the short one's whole set (report.json and index.html of one
  run, its manifest listing exactly what is there, no hidden file left);
- a long report racing an import into the same folder: the same, with the
  import's files;
- two reports started together, several times: each pair is serialised
  (exit codes 0 0, 0 3 or 3 0, never 3 3), the folder holds one whole set;
- two editors (cmr edit --script, under Xvfb; skipped without xvfb-run)
  open one spline file; the second to save is refused with one line
  (exit 3) instead of replacing the first one's save (io/output_guard.hpp).

Usage: concurrency_test.py CMR WORKDIR
"""
import json
import os
import shutil
import subprocess
import sys
import time

CMR = os.path.abspath(sys.argv[1])
WORK = sys.argv[2]
failures = []
LINE = "another cmr run wrote this folder while this one ran"


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def svg(path, n, dx=0):
    with open(path, "w") as f:
        f.write('<svg xmlns="http://www.w3.org/2000/svg">\n')
        for i in range(n):
            x, y = (i % 300) * 10 + dx, (i // 300) * 10
            f.write(f'<path d="M{x} {y} C{x + 3} {y + 5} {x + 6} {y - 2} {x + 9} {y + 4}"/>\n')
        f.write("</svg>\n")


def start(args):
    return subprocess.Popen([CMR] + args, cwd=WORK, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)


def finish(p):
    _, err = p.communicate(timeout=600)
    return p.returncode, [l for l in err.decode(errors="replace").splitlines()
                          if l.strip() and not l.startswith("note: no GPU")]


def one_whole_set(folder):
    """(ok, what): the folder's files are exactly its manifest's, none hidden left, and
    a report's report.json and index.html are of one run."""
    names = sorted(os.listdir(folder))
    hidden = [n for n in names if n.startswith(".") and n != ".cmr-manifest"]
    if hidden:
        return False, "hidden files left: %s" % hidden
    listed = sorted(l.split(" ", 3)[3] for l in open(os.path.join(folder, ".cmr-manifest")).read().splitlines()[1:])
    shown = [n for n in names if n != ".cmr-manifest"]
    if listed != shown:
        return False, "manifest %s, folder %s" % (listed[:5], shown[:5])
    if "report.json" in shown:
        doc = json.load(open(os.path.join(folder, "report.json")))
        page = open(os.path.join(folder, "index.html")).read()
        files = {sp["file"].split(":")[0] for sp in doc["splines"]}
        if len(files) != 1 or next(iter(files)) not in page or len(doc["splines"]) != doc["summary"]["splines"]:
            return False, "report.json (%s) and index.html of different runs" % files
        return True, "report of %s, %d splines" % (files, len(doc["splines"]))
    return True, "%d imported files" % len(shown)


shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
svg(os.path.join(WORK, "long.svg"), 12000)
svg(os.path.join(WORK, "short.svg"), 5, dx=7)

# 1. A short report commits while a long one runs.
out = "rep"
long_run = start(["report", "long.svg", "--out", out, "--no-thumbnails"])
time.sleep(0.5)
rc_short, err_short = finish(start(["report", "short.svg", "--out", out, "--no-thumbnails"]))
rc_long, err_long = finish(long_run)
check(rc_short == 0, f"report: the short run commits (exit {rc_short}: {err_short})")
check(rc_long == 3 and len(err_long) == 1 and LINE in err_long[0],
      f"report: the long run, overtaken, exits 3 with one line ({rc_long}: {err_long})")
ok, what = one_whole_set(os.path.join(WORK, out))
check(ok and "short.svg" in what, f"report: the folder holds the short run's whole set ({what})")

# 2. An import commits while a long report runs into the same folder.
out = "mixed"
long_run = start(["report", "long.svg", "--out", out, "--no-thumbnails"])
time.sleep(0.5)
rc_imp, err_imp = finish(start(["import", "short.svg", "--out", out]))
rc_long, err_long = finish(long_run)
check(rc_imp == 0, f"import: commits (exit {rc_imp}: {err_imp})")
check(rc_long == 3 and len(err_long) == 1 and LINE in err_long[0],
      f"import then report: the report, overtaken, exits 3 with one line ({rc_long}: {err_long})")
ok, what = one_whole_set(os.path.join(WORK, out))
check(ok and "5 imported" in what, f"import then report: the folder holds the import's whole set ({what})")

# 3. Two reports started together, several times.
svg(os.path.join(WORK, "mid_a.svg"), 1500)
svg(os.path.join(WORK, "mid_b.svg"), 1600, dx=3)
for k in range(4):
    out = "pair%d" % k
    a = start(["report", "mid_a.svg", "--out", out, "--no-thumbnails"])
    b = start(["report", "mid_b.svg", "--out", out, "--no-thumbnails"])
    (ra, ea), (rb, eb) = finish(a), finish(b)
    serialised = (ra, rb) in ((0, 0), (0, 3), (3, 0))
    said = all(len(e) == 1 and LINE in e[0] for r, e in ((ra, ea), (rb, eb)) if r == 3)
    ok, what = one_whole_set(os.path.join(WORK, out))
    check(serialised and said and ok, f"two reports at once #{k}: exits {ra} {rb}, {what}")

# 4. Two editors save one file (cmr edit's scripted mode, under one Xvfb):
# the second save must not replace the first one's work.
if shutil.which("xvfb-run") is None:
    print("skip: two editors need xvfb-run")
else:
    src = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples", "figures", "fig8.json")
    shutil.copy(src, os.path.join(WORK, "both.json"))
    knots = len(json.load(open(os.path.join(WORK, "both.json")))["knots"])
    with open(os.path.join(WORK, "slow.txt"), "w") as f:  # opens, waits (1500 frames: seconds, so the fast one saves first), changes, saves
        f.write("wait 1500\nelevate\nsave\nquit\n")
    with open(os.path.join(WORK, "fast.txt"), "w") as f:  # opens, inserts a knot, saves at once
        f.write("insert 3.5\nsave\nquit\n")
    env = dict(os.environ, VK_DRIVER_FILES="/usr/share/vulkan/icd.d/lvp_icd.x86_64.json")
    shell = (f"{CMR} edit both.json --script slow.txt 2>slow.err & p=$!; sleep 1; "
             f"{CMR} edit both.json --script fast.txt 2>fast.err; b=$?; wait $p; a=$?; echo $a $b")
    # -f: an X authority file of our own; without it xvfb-run may exit 5
    # before it stops its Xvfb (tests/tools/edit_test.cpp's kXvfbAuth).
    auth = os.path.join(WORK, "xauthority")
    open(auth, "w").close()
    r = subprocess.run(["xvfb-run", "-a", "-f", auth, "-s", "-screen 0 800x600x24", "sh", "-c", shell], cwd=WORK, env=env,
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=300)
    codes = r.stdout.decode().split()
    slow_err = [l for l in open(os.path.join(WORK, "slow.err")).read().splitlines() if "changed on disk" in l]
    saved = json.load(open(os.path.join(WORK, "both.json")))
    check(codes[-2:] == ["3", "0"], f"two editors: the fast one saves (0), the slow one is refused (3) (got {codes})")
    check(len(slow_err) == 1, f"two editors: the slow one says so in one line ({slow_err})")
    check(len(saved["knots"]) == knots + 1 and saved["degree"] == json.load(open(src))["degree"],
          "two editors: the file holds the fast editor's save (one knot more, degree as before), nothing mixed")
    check(not [n for n in os.listdir(WORK) if n.startswith(".cmr-")], "two editors: no hidden file left")

print(f"{len(failures)} failed")
sys.exit(1 if failures else 0)
