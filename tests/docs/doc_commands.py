#!/usr/bin/env python3
"""Keeps the README and the docs/ pages true.

1. Every relative link in README.md and docs/*.md points at a file that
   exists (and, for page#anchor, at a heading of that page).
2. Every command shown in a fenced ```sh block of those pages that starts
   with `cmr ` (continuation lines ending in a backslash joined) is run with
   the built binary, in order, in a fresh scratch folder per block where
   `examples/` is the repository's (a `mkdir -p DIR` line in the block is run
   too), and must exit 0 — or with the code a trailing comment `# exit N`
   states. A pipeline of cmr commands (`cmr A | cmr B -`) runs as one: each
   command before the last must exit 0, the last as stated.

Usage: doc_commands.py SOURCE_DIR CMR_BINARY
Prints one line per check and 'N passed, N failed' at the end; exits 1 on any
failure.
"""
import os
import re
import shlex
import subprocess
import sys
import tempfile

source, binary = sys.argv[1], sys.argv[2]
pages = [os.path.join(source, "README.md")] + sorted(
    os.path.join(source, "docs", f) for f in os.listdir(os.path.join(source, "docs")) if f.endswith(".md"))
passed = failed = 0


def report(ok, what):
    global passed, failed
    print(("PASS " if ok else "FAIL ") + what)
    if ok:
        passed += 1
    else:
        failed += 1


def anchors(path):
    """GitHub's heading anchors of a Markdown page."""
    out = set()
    in_code = False
    for line in open(path, encoding="utf-8"):
        if line.startswith("```"):
            in_code = not in_code
        if in_code or not line.startswith("#"):
            continue
        text = line.lstrip("#").strip().lower()
        text = re.sub(r"[^\w\- ]", "", text)
        out.add(text.replace(" ", "-"))
    return out


def strip_code(text):
    return re.sub(r"```.*?```", "", text, flags=re.S)


for page in pages:
    rel = os.path.relpath(page, source)
    text = open(page, encoding="utf-8").read()
    for target in re.findall(r"\]\(([^)\s]+)\)", strip_code(text)):
        if re.match(r"[a-z]+:", target):
            continue  # an absolute URL: not checked offline
        path, _, anchor = target.partition("#")
        resolved = os.path.normpath(os.path.join(os.path.dirname(page), path)) if path else page
        ok = os.path.exists(resolved)
        if ok and anchor and resolved.endswith(".md"):
            ok = anchor in anchors(resolved)
        report(ok, f"{rel}: link {target}")

    for block in re.findall(r"```(?:sh|bash)\n(.*?)```", text, flags=re.S):
        joined, pending = [], ""
        for line in block.split("\n"):
            if line.rstrip().endswith("\\"):
                pending += line.rstrip()[:-1] + " "
                continue
            joined.append(pending + line)
            pending = ""
        # One scratch folder per block: its commands run in order, so a
        # `mkdir -p DIR` line prepares what the next `cmr` line writes into.
        with tempfile.TemporaryDirectory() as scratch:
            os.symlink(os.path.join(source, "examples"), os.path.join(scratch, "examples"))
            for line in joined:
                stripped = line.strip()
                if stripped.startswith("mkdir "):
                    subprocess.run(shlex.split(stripped.split(" #")[0]), cwd=scratch, check=True)
                    continue
                if not stripped.startswith("cmr "):
                    continue
                expect = 0
                m = re.search(r"#\s*exit\s+(\d+)", stripped)
                if m:
                    expect = int(m.group(1))
                command = stripped.split(" #")[0].strip()
                stages = [[]]
                for word in shlex.split(command):
                    if word == "|":
                        stages.append([])
                    else:
                        stages[-1].append(word)
                env = dict(os.environ)
                env.setdefault("VK_DRIVER_FILES", "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json")
                if any(not st or st[0] != "cmr" for st in stages):
                    report(False, f"{rel}: {command} -> a pipeline stage that is not a cmr command")
                    continue
                procs, upstream = [], None
                for k, st in enumerate(stages):
                    last = k + 1 == len(stages)
                    procs.append(subprocess.Popen([binary] + st[1:], cwd=scratch, stdin=upstream,
                                                  stdout=subprocess.DEVNULL if last else subprocess.PIPE,
                                                  stderr=subprocess.PIPE, env=env))
                    upstream = procs[-1].stdout
                for p in procs[:-1]:
                    p.stdout.close()  # the next stage holds it
                    p.stdout = None
                errors = [p.communicate(timeout=600)[1] for p in reversed(procs)][::-1]
                codes = [p.returncode for p in procs]
                ok = codes[-1] == expect and all(c == 0 for c in codes[:-1])
                bad = next((k for k, c in enumerate(codes) if (c != expect if k + 1 == len(codes) else c != 0)), -1)
                detail = "" if ok else (f" -> exit {codes[bad]}: "
                                        f"{errors[bad].decode(errors='replace').strip()[:300]}")
                report(ok, f"{rel}: {command}{detail}")

print(f"{passed} passed, {failed} failed")
sys.exit(1 if failed else 0)
