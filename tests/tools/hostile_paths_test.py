#!/usr/bin/python3
"""Hostile output paths (issue 42 item 9): one line, the documented exit, and
no file outside the named output touched.

- names with a newline (or another control character): exit 2, nothing made;
- a name longer than NAME_MAX, a path longer than PATH_MAX: exit 2, one line;
- the output folder removed while a report runs: exit 2 or 3, one line, no
  file made anywhere else;
- with a second user (`setpriv --reuid=nobody`, skipped when not root or
  without setpriv), in a sticky folder writable by all (as /tmp):
  - a link nobody planted at the output name, aimed at root's file: not
    followed (exit 2, one line), root's file unchanged;
  - a link nobody planted as the output folder, aimed at root's folder:
    not followed, root's folder unchanged;
  - nobody swapping a link in and out at the output name while root writes
    there 20 times: root's file unchanged, every run exit 0 or 2.

Usage: hostile_paths_test.py CMR SOURCE_DIR WORKDIR
"""
import os
import shutil
import subprocess
import sys
import time

CMR = os.path.abspath(sys.argv[1])
SRC = os.path.abspath(sys.argv[2])
WORK = os.path.abspath(sys.argv[3])
FIG8 = os.path.join(SRC, "examples", "figures", "fig8.json")
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def run(args, timeout=300):
    p = subprocess.run([CMR] + args, cwd=WORK, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, timeout=timeout)
    return p.returncode, [l for l in p.stderr.decode(errors="replace").splitlines()
                          if l.strip() and not l.startswith("note: no GPU")]


def snapshot(folder):
    out = {}
    for root, dirs, files in os.walk(folder):
        for n in dirs + files:
            p = os.path.join(root, n)
            st = os.lstat(p)
            out[os.path.relpath(p, folder)] = (st.st_ino, st.st_size, st.st_mtime_ns)
    return out


def region(png):
    return ["region", FIG8, "--point", "3", "--size", "32x32", "--backend", "cpu", "--png", png]


shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
os.chmod(WORK, 0o755)

# Newlines and control characters.
before = snapshot(WORK)
for args, what in ((region("a\nb.png"), "region --png 'a\\nb.png'"),
                   (["report", FIG8, "--out", "r\nq", "--no-thumbnails"], "report --out 'r\\nq'"),
                   (region("tab\there.png"), "region --png with a tab"),
                   (region("esc\x1b[2J.png"), "region --png with ESC")):
    rc, err = run(args)
    check(rc == 2 and len(err) == 1 and "control character" in err[0], f"{what}: exit 2, one line ({rc}: {err})")
check(snapshot(WORK) == before, "control characters: nothing made")

# Long names.
rc, err = run(region("d" * 300 + ".png"))
check(rc == 2 and len(err) == 1 and "too long" in err[0], f"a 304-byte name: exit 2, one line ({rc}: {err[:1]})")
deep = "/".join(["x" * 250] * 20) + "/a.png"
rc, err = run(region(deep))
check(rc == 2 and len(err) == 1, f"a path of {len(deep)} bytes (> PATH_MAX): exit 2, one line ({rc})")
rc, err = run(["report", FIG8, "--out", deep[:-6] + "/r", "--no-thumbnails"])
check(rc == 2 and len(err) == 1, f"report --out of > PATH_MAX: exit 2, one line ({rc})")
check(snapshot(WORK) == before, "long names: nothing made")

# The output folder removed during a run.
with open(os.path.join(WORK, "long.svg"), "w") as f:
    f.write('<svg xmlns="http://www.w3.org/2000/svg">\n')
    for i in range(8000):
        x, y = (i % 300) * 10, (i // 300) * 10
        f.write(f'<path d="M{x} {y} C{x + 3} {y + 5} {x + 6} {y - 2} {x + 9} {y + 4}"/>\n')
    f.write("</svg>\n")
before = snapshot(WORK)
p = subprocess.Popen([CMR, "report", "long.svg", "--out", "gone/sub", "--no-thumbnails"], cwd=WORK,
                     stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
for _ in range(200):  # until the run made its folder
    if os.path.isdir(os.path.join(WORK, "gone", "sub")):
        break
    time.sleep(0.02)
shutil.rmtree(os.path.join(WORK, "gone"), ignore_errors=True)
_, err = p.communicate(timeout=300)
err = [l for l in err.decode(errors="replace").splitlines() if l.strip() and not l.startswith("note: no GPU")]
after = snapshot(WORK)
check(p.returncode in (2, 3) and len(err) == 1, f"folder removed during a report: exit 2 or 3, one line ({p.returncode}: {err})")
check(after == before, f"folder removed: nothing made elsewhere ({sorted(set(after) - set(before))[:5]})")

# A second user in a shared folder.
can = os.geteuid() == 0 and shutil.which("setpriv") is not None
if not can:
    print("skip: a second user needs root and setpriv")
else:
    def as_nobody(shell):
        return subprocess.run(["setpriv", "--reuid=nobody", "--regid=nogroup", "--clear-groups", "sh", "-c", shell],
                              cwd=WORK).returncode

    shared = os.path.join(WORK, "shared")
    os.makedirs(shared)
    os.chmod(shared, 0o1777)
    private = os.path.join(WORK, "private")
    os.makedirs(private)
    victim = os.path.join(private, "victim.txt")
    with open(victim, "w") as f:
        f.write("precious\n")
    keep = snapshot(private)

    check(as_nobody(f"ln -s {victim} {shared}/out.png") == 0, "nobody plants shared/out.png -> root's victim.txt")
    rc, err = run(region(os.path.join(shared, "out.png")))
    check(rc == 2 and len(err) == 1 and "not followed" in err[0], f"root's --png through nobody's link: exit 2, one line ({rc}: {err})")
    check(open(victim).read() == "precious\n" and snapshot(private) == keep, "root's victim.txt unchanged")

    check(as_nobody(f"ln -s {private} {shared}/rep") == 0, "nobody plants shared/rep -> root's folder")
    rc, err = run(["report", FIG8, "--out", os.path.join(shared, "rep"), "--no-thumbnails"])
    check(rc == 2 and len(err) == 1 and "not followed" in err[0], f"root's report --out through nobody's link: exit 2, one line ({rc}: {err})")
    check(snapshot(private) == keep, "root's folder unchanged")

    # nobody swaps a link in and out at the name root writes.
    as_nobody(f"rm -f {shared}/out.png {shared}/rep")
    swapper = subprocess.Popen(["setpriv", "--reuid=nobody", "--regid=nogroup", "--clear-groups", "sh", "-c",
                                f"while :; do ln -sf {victim} {shared}/swap.png; rm -f {shared}/swap.png; done"],
                               cwd=WORK, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    codes = []
    try:
        for _ in range(20):
            rc, err = run(region(os.path.join(shared, "swap.png")))
            codes.append(rc)
            if rc not in (0, 2) or len(err) > 1:
                check(False, f"swap: exit {rc}, {err}")
    finally:
        swapper.kill()
        swapper.wait()
    check(all(c in (0, 2) for c in codes), f"20 writes while nobody swaps a link: exits {sorted(set(codes))}")
    check(open(victim).read() == "precious\n" and snapshot(private) == keep, "root's victim.txt unchanged by the swaps")

print(f"{len(failures)} failed")
sys.exit(1 if failures else 0)
