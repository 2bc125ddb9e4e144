#!/usr/bin/env python3
"""Keeps examples/ci/cmr-qa.yml true (docs/report.md, "A GitHub Actions workflow").

The workflow is parsed as YAML; its steps must upload the SARIF file cmr
writes (github/codeql-action/upload-sarif), post the Markdown summary cmr
writes as the pull request's comment, and end with cmr's exit code. Then its
"Report" step's cmr command is run as the workflow runs it, in a scratch
checkout (a font under $QA_INPUT; the glyphs cut to a few for speed), after
the baseline is accepted as docs/report.md's first step says: it must exit 0
(nothing new), write every file the later steps read, with SARIF URIs
relative to the checkout's root.

Usage: ci_workflow.py SOURCE_DIR CMR_BINARY FONT
"""
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

import yaml

source, binary, font = sys.argv[1], sys.argv[2], sys.argv[3]
failed = 0


def check(ok, what):
    global failed
    print(("PASS " if ok else "FAIL ") + what)
    failed += 0 if ok else 1


flow = yaml.safe_load(open(os.path.join(source, "examples", "ci", "cmr-qa.yml"), encoding="utf-8"))
env = flow["env"]
steps = flow["jobs"]["qa"]["steps"]
check(flow["permissions"].get("security-events") == "write", "permission to upload SARIF")
check(flow["permissions"].get("pull-requests") == "write", "permission to comment")
report = next(s for s in steps if s.get("id") == "qa")
command = re.search(r"^\s*(cmr report .*?)(?<!\\)$", report["run"].replace("\\\n", " "), re.M).group(1)
outputs = dict(re.findall(r"--(sarif|markdown|junit|out|baseline) (\S+)", command))
sarif = next((s for s in steps if s.get("uses", "").startswith("github/codeql-action/upload-sarif@")), None)
check(sarif is not None and sarif["with"]["sarif_file"] == outputs["sarif"], "upload-sarif uploads cmr's SARIF file")
comment = next((s for s in steps if "gh pr comment" in s.get("run", "")), {})
check("--body-file " + outputs["markdown"] in comment.get("run", ""), "the comment is cmr's Markdown summary")
check(steps[-1]["run"].strip() == "exit ${{ steps.qa.outputs.code }}", "the last step exits with cmr's code")

with tempfile.TemporaryDirectory() as root:
    os.makedirs(os.path.join(root, env["QA_INPUT"]))
    shutil.copy(font, os.path.join(root, env["QA_INPUT"], os.path.basename(font)))
    shell_env = dict(os.environ)
    shell_env.update({k: str(v) for k, v in env.items()})
    shell_env["QA_GLYPHS"] = "O,o,H,e"
    shell_env.pop("CI", None)
    run = command.replace("cmr ", binary + " ", 1)
    # docs/report.md, step 1: accept today's state (the command without the baseline).
    accept = re.sub(r"--out \S+ --baseline \S+", "--out qa/accepted", run)
    accept = re.sub(r" --(sarif|markdown|junit) \S+", "", accept)
    first = subprocess.run(accept, shell=True, cwd=root, env=shell_env, capture_output=True, text=True)
    check(first.returncode in (0, 1) and os.path.exists(os.path.join(root, outputs["baseline"])),
          "the baseline is accepted: " + first.stderr.strip())
    # The workflow's command, from another checkout folder: nothing new.
    moved = root + "-checkout"
    shutil.move(root, moved)
    try:
        second = subprocess.run(run, shell=True, cwd=moved, env=shell_env, capture_output=True, text=True)
        check(second.returncode == 0, "the workflow's command passes against its baseline in another checkout: " +
              second.stdout.strip() + second.stderr.strip())
        for key in ("sarif", "markdown", "junit"):
            check(os.path.exists(os.path.join(moved, outputs[key])), outputs[key] + " is written")
        summary = open(os.path.join(moved, outputs["markdown"]), encoding="utf-8").read()
        check(len(summary) < 65536 and summary.startswith("## cmr report: no new findings"), "the summary")
        log = json.load(open(os.path.join(moved, outputs["sarif"]), encoding="utf-8"))
        uris = {r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] for r in log["runs"][0]["results"]}
        bases = {r["locations"][0]["physicalLocation"]["artifactLocation"].get("uriBaseId") for r in log["runs"][0]["results"]}
        want = env["QA_INPUT"] + "/" + os.path.basename(font)
        check(uris == {want} and bases == {"SRCROOT"}, "SARIF URIs relative to the checkout: " + str(uris))
        check(log["runs"][0]["originalUriBaseIds"]["SRCROOT"]["uri"] == "file://" + os.path.realpath(moved) + "/",
              "SRCROOT is the checkout")
    finally:
        shutil.move(moved, root)

print("%d failed" % failed)
sys.exit(1 if failed else 0)
