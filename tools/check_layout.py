#!/usr/bin/env python3
"""The Done-when of issue 41 (the house's layout), checked on the source tree.

    python3 tools/check_layout.py [--root DIR] [--check NAME ...] [--list]

Checks (all by default; --check NAME, repeatable, runs only those named):
  share    no library folder holds more than 25 % of the non-test code
  lines    no library source file is over 1,000 lines
  getenv   no getenv in a library (the environment is read in tools/ only)
  flags    no library string literal names a CLI flag (`--word` inside a
           string literal; libraries name option fields, spline/fields.hpp,
           and tools/field_flags.hpp maps them to flags)
  backend  no backend string compare in tools/ (a backend is chosen through
           vk/backend_choice.hpp, not by comparing its name)
  hdr      no magic hdr[N] index in vk/ (buffer headers have named fields)
  fieldmap every field("NAME") a library marks has its flag in the command's
           one table (tools/field_flags.hpp), so the command never prints a
           bare field name where it printed a flag
  public   in the folders split out of bezierize/ (SPLIT), every header is
           either named in the folder README's "Public header:" paragraph
           or says "Internal" in its opening comment

The libraries are the folders in LIBRARIES that exist; tools/ is the command
(it may name flags) and tests/ the tests. "Code" is C, C++ and GLSL text
(.c .cc .cpp .h .hpp .glsl .frag .vert .comp) outside tests/, counted in
lines. Each failure is one line naming the check, the file (and line) and
why; the exit status is 1 when any check fails, else 0.

KNOWN below lists the exceptions, each skipped by its check and printed as
"known:" so that it stays visible (today one: a glslangValidator flag, not
cmr's). The ctest test `layout` (tests/tools/CMakeLists.txt) runs every
check.
"""
import argparse
import os
import re
import sys

LIBRARIES = ["spline", "numeric", "bezierize", "region", "design", "vk", "io", "draw", "report", "step"]
CODE_EXT = (".c", ".cc", ".cpp", ".h", ".hpp", ".glsl", ".frag", ".vert", ".comp")
SOURCE_EXT = (".c", ".cc", ".cpp", ".h", ".hpp")
MAX_SHARE = 0.25
MAX_LINES = 1000
CHECKS = ["share", "lines", "getenv", "flags", "backend", "hdr", "fieldmap", "public"]
SPLIT = ["numeric", "bezierize", "region", "design"]
FIELD_TABLE = "tools/field_flags.hpp"

# Known exceptions, one place: {check: {path or folder: why}}. Paths are
# relative to the root, with '/'; a flag entry may name "path:--flag".
KNOWN = {
    "flags": {
        # glslangValidator's option, not cmr's: the message tells how the
        # shader must be compiled.
        "vk/context.cpp:--target-env": "a glslangValidator flag",
    },
}


def strip_comments(text):
    """C/C++ text with comments blanked (string and character literals kept),
    line breaks kept so that line numbers stay."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if c == "/" and i + 1 < n and text[i + 1] == "/":
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif c == "/" and i + 1 < n and text[i + 1] == "*":
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append("".join(ch if ch == "\n" else " " for ch in text[i:j]))
            i = j
        elif c == "R" and text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = re.match(r'R"([^(\s]{0,16})\(', text[i:])
            if not m:
                out.append(c)
                i += 1
                continue
            end = text.find(")" + m.group(1) + '"', i)
            end = n if end < 0 else end + len(m.group(1)) + 2
            out.append(text[i:end])
            i = end
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            out.append(text[i:j + 1])
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


STRING = re.compile(r'"((?:[^"\\\n]|\\.)*)"')
FLAG = re.compile(r"(?<![A-Za-z0-9_-])--([a-z][a-z0-9]*(?:-[a-z0-9]+)*)")
BACKEND_COMPARE = re.compile(
    r'\bbackend\w*(?:\(\))?\s*(?:==|!=)\s*"|"[^"\n]*"\s*(?:==|!=)\s*\w*backend\b'
    r'|(?:==|!=)\s*"(?:cpu|vulkan)"|"(?:cpu|vulkan)"\s*(?:==|!=)'
    r'|\.compare\(\s*"(?:cpu|vulkan|auto)"')
HDR = re.compile(r"\bhdr\s*\[\s*\d+\s*\]")


def files_under(root, folder, exts):
    base = os.path.join(root, folder)
    for dirpath, dirnames, filenames in os.walk(base):
        dirnames[:] = sorted(d for d in dirnames if not d.startswith(".") and d != "build")
        for f in sorted(filenames):
            if f.endswith(exts):
                path = os.path.join(dirpath, f)
                yield os.path.relpath(path, root).replace(os.sep, "/"), path


def read(path):
    with open(path, encoding="utf-8", errors="replace") as f:
        return f.read()


def line_count(path):
    with open(path, "rb") as f:
        return sum(1 for _ in f)


def code_folders(root):
    """Top-level folders that hold non-test code (not tests/, build trees, hidden)."""
    out = []
    for d in sorted(os.listdir(root)):
        full = os.path.join(root, d)
        if not os.path.isdir(full) or d.startswith(".") or d == "tests" or d.startswith("build"):
            continue
        out.append(d)
    return out


def check_share(root, libs, failures, known):
    lines = {}
    for d in code_folders(root):
        lines[d] = sum(line_count(p) for _, p in files_under(root, d, CODE_EXT))
    total = sum(lines.values())
    for lib in libs:
        share = lines.get(lib, 0) / total if total else 0
        msg = f"share: {lib}/ holds {share:.1%} of the non-test code ({lines.get(lib, 0)} of {total} lines; at most {MAX_SHARE:.0%})"
        if share > MAX_SHARE:
            (known if lib in KNOWN.get("share", {}) else failures).append(msg)


def check_lines(root, libs, failures, known):
    for lib in libs:
        for rel, path in files_under(root, lib, SOURCE_EXT):
            n = line_count(path)
            if n > MAX_LINES:
                msg = f"lines: {rel} has {n} lines (at most {MAX_LINES})"
                (known if rel in KNOWN.get("lines", {}) else failures).append(msg)


def check_getenv(root, libs, failures, known):
    for lib in libs:
        for rel, path in files_under(root, lib, SOURCE_EXT):
            code = strip_comments(read(path))
            for no, line in enumerate(code.split("\n"), 1):
                if re.search(r"\b(?:secure_)?getenv\s*\(", line):
                    msg = f"getenv: {rel}:{no} reads the environment (an option of the request; read it in tools/)"
                    (known if rel in KNOWN.get("getenv", {}) else failures).append(msg)


def check_flags(root, libs, failures, known):
    for lib in libs:
        for rel, path in files_under(root, lib, SOURCE_EXT):
            code = strip_comments(read(path))
            for no, line in enumerate(code.split("\n"), 1):
                if line.lstrip().startswith("#include"):
                    continue
                for m in STRING.finditer(line):
                    for f in FLAG.finditer(m.group(1)):
                        flag = "--" + f.group(1)
                        msg = (f"flags: {rel}:{no} names the CLI flag {flag} in a string "
                               f"(name the field: spline/fields.hpp, tools/field_flags.hpp)")
                        key = f"{rel}:{flag}"
                        (known if key in KNOWN.get("flags", {}) or rel in KNOWN.get("flags", {}) else failures).append(msg)


def check_backend(root, failures, known):
    for rel, path in files_under(root, "tools", SOURCE_EXT):
        code = strip_comments(read(path))
        for no, line in enumerate(code.split("\n"), 1):
            if BACKEND_COMPARE.search(line):
                msg = f"backend: {rel}:{no} compares a backend by its name (choose it through vk/backend_choice.hpp)"
                (known if rel in KNOWN.get("backend", {}) else failures).append(msg)


def check_hdr(root, failures, known):
    for rel, path in files_under(root, "vk", SOURCE_EXT + (".glsl", ".frag")):
        code = strip_comments(read(path))
        for no, line in enumerate(code.split("\n"), 1):
            if HDR.search(line):
                msg = f"hdr: {rel}:{no} indexes a buffer header by number (name the field)"
                (known if rel in KNOWN.get("hdr", {}) else failures).append(msg)


def check_fieldmap(root, libs, failures, known):
    table_path = os.path.join(root, FIELD_TABLE)
    table = set(re.findall(r'\{"([^"]+)", "--[a-z0-9-]+"\}', read(table_path))) if os.path.exists(table_path) else set()
    for lib in libs:
        for rel, path in files_under(root, lib, SOURCE_EXT):
            code = strip_comments(read(path))
            for no, line in enumerate(code.split("\n"), 1):
                for m in re.finditer(r'\bfield\("([^"]+)"\)', line):
                    if m.group(1) not in table:
                        msg = f"fieldmap: {rel}:{no} marks the field {m.group(1)}, which {FIELD_TABLE} does not map to a flag"
                        (known if rel in KNOWN.get("fieldmap", {}) else failures).append(msg)


def readme_public_headers(root, folder):
    """The headers named in FOLDER/README.md's "Public header:" paragraph."""
    path = os.path.join(root, folder, "README.md")
    if not os.path.exists(path):
        return None
    m = re.search(r"^Public headers?:(.*?)(?:\n\s*\n|\n[A-Z][a-z]+:|\Z)", read(path), re.M | re.S)
    return set(re.findall(r"`(?:" + folder + r"/)?([A-Za-z0-9_]+\.hpp)`", m.group(1))) if m else set()


def check_public(root, failures, known):
    for folder in SPLIT:
        if not os.path.isdir(os.path.join(root, folder)):
            continue
        public = readme_public_headers(root, folder)
        if public is None:
            failures.append(f"public: {folder}/README.md is missing (it names the folder's public header)")
            continue
        for rel, path in files_under(root, folder, (".hpp",)):
            name = os.path.basename(rel)
            if name in public:
                continue
            opening = re.match(r"(?:\s*(?://[^\n]*|#pragma once)\n)*", read(path)).group(0)
            if not re.search(r"\bInternal\b", opening):
                msg = f"public: {rel} is not a public header of {folder}/README.md and does not say it is internal"
                (known if rel in KNOWN.get("public", {}) else failures).append(msg)


def self_test():
    """Each check fails on a small tree made to break it, and passes on its fix."""
    import tempfile

    def run(files, check):
        with tempfile.TemporaryDirectory() as root:
            for rel, text in files.items():
                path = os.path.join(root, rel)
                os.makedirs(os.path.dirname(path), exist_ok=True)
                with open(path, "w", encoding="utf-8") as f:
                    f.write(text)
            libs = [d for d in LIBRARIES if os.path.isdir(os.path.join(root, d))]
            failures, known = [], []
            {"share": lambda: check_share(root, libs, failures, known),
             "lines": lambda: check_lines(root, libs, failures, known),
             "getenv": lambda: check_getenv(root, libs, failures, known),
             "flags": lambda: check_flags(root, libs, failures, known),
             "backend": lambda: check_backend(root, failures, known),
             "hdr": lambda: check_hdr(root, failures, known),
             "fieldmap": lambda: check_fieldmap(root, libs, failures, known),
             "public": lambda: check_public(root, failures, known)}[check]()
            return failures

    small = {"tools/main.cpp": "int main() {}\n" * 40, "io/a.cpp": "int a;\n" * 10, "step/a.cpp": "int a;\n" * 10}
    cases = [  # (check, breaking files, passing files)
        ("share", {**small, "spline/a.cpp": "int x;\n" * 40}, {**small, "spline/a.cpp": "int x;\n" * 10}),
        ("lines", {"spline/big.cpp": "int x;\n" * (MAX_LINES + 1)}, {"spline/big.cpp": "int x;\n" * MAX_LINES}),
        ("getenv", {"vk/c.cpp": 'const char* e = std::getenv("X");\n'},
         {"vk/c.cpp": '// std::getenv("X") is read in tools/\n'}),
        ("flags", {"report/r.cpp": 'throw InputError("bad " "x; use --max-move 2");\n'},
         {"report/r.cpp": '// --max-move in a comment\nthrow InputFieldError(field("max_move") + " x"); int y = a-- - --b;\n'}),
        ("backend", {"tools/cmd.cpp": 'if (a.backend == "cpu") run();\n'},
         {"tools/cmd.cpp": 'auto b = make_region_backend(choice);\n'}),
        ("hdr", {"vk/p.cpp": "p.hdr[3] = 1;\n"}, {"vk/p.cpp": "p.hdr[SPACE_HDR_MODE] = 1;\n"}),
        ("fieldmap", {FIELD_TABLE: '{"max_move", "--max-move"},\n', "spline/f.cpp": 'field("max_move") + field("grid");\n'},
         {FIELD_TABLE: '{"max_move", "--max-move"},\n{"grid", "--grid"},\n', "spline/f.cpp": 'field("max_move") + field("grid");\n'}),
        ("public", {"region/README.md": "Public header: `region/region.hpp`.\n", "region/region.hpp": "#pragma once\n",
                    "region/kernel.hpp": "#pragma once\n// The kernel.\nint f(); // Internal\n"},
         {"region/README.md": "Public header: `region/region.hpp`.\n", "region/region.hpp": "#pragma once\n",
          "region/kernel.hpp": "#pragma once\n// Internal to cmr::region.\n// The kernel.\n"}),
    ]
    bad = 0
    for check, breaking, passing in cases:
        got_bad, got_good = run(breaking, check), run(passing, check)
        ok = len(got_bad) == 1 and not got_good
        bad += not ok
        print(f"self-test {check}: {'ok' if ok else 'WRONG'} (breaking: {got_bad}; passing: {got_good})")
    return 1 if bad else 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--root", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    ap.add_argument("--check", action="append", choices=CHECKS, help="run only this check (repeatable)")
    ap.add_argument("--list", action="store_true", help="print what each check looked at")
    ap.add_argument("--self-test", action="store_true", help="check the checks on small trees made to break them")
    args = ap.parse_args()
    if args.self_test:
        return self_test()
    root = args.root
    libs = [d for d in LIBRARIES if os.path.isdir(os.path.join(root, d))]
    checks = args.check or CHECKS
    failures, known = [], []
    if "share" in checks:
        check_share(root, libs, failures, known)
    if "lines" in checks:
        check_lines(root, libs, failures, known)
    if "getenv" in checks:
        check_getenv(root, libs, failures, known)
    if "flags" in checks:
        check_flags(root, libs, failures, known)
    if "backend" in checks:
        check_backend(root, failures, known)
    if "hdr" in checks:
        check_hdr(root, failures, known)
    if "fieldmap" in checks:
        check_fieldmap(root, libs, failures, known)
    if "public" in checks:
        check_public(root, failures, known)
    if args.list:
        print("libraries: " + " ".join(libs))
        print("checks: " + " ".join(checks))
    for k in known:
        print("known: " + k)
    for f in failures:
        print("FAIL " + f)
    print(f"check_layout: {len(failures)} failure(s), {len(known)} known, checks: {', '.join(checks)}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
