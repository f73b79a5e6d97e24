#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0
"""The documentation points at what is there: every relative link of the
tracked Markdown files names an existing file (and, with #anchor, one of
its headings), every file path in backticks that starts at a top folder of
the tree exists, nothing points outside the repository (../shared, the
project's notes beside it), the README stays short and gives the test
command, and tests/README.md maps every source file to its tests. Prints each problem as FILE:LINE: what;
exits 1 if there was one.

Usage: tests/check-docs.py [TOP]   (default: the repository of this file)
"""
import fnmatch
import os
import re
import subprocess
import sys

top = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
files = subprocess.run(["git", "ls-files", "*.md"], cwd=top, capture_output=True, text=True,
                       check=True).stdout.split()
# Backticked paths under these folders are checked: `kmod/engine/x4_req.c`.
roots = ("kmod/", "lib/", "include/", "tools/", "tests/", "machines/", "docs/", ".ci/")
link_re = re.compile(r"\]\(([^)\s]+)\)")
code_re = re.compile(r"`([^`\s]+)`")
problems = []


def anchors(path):
    """GitHub's anchors of a Markdown file's headings."""
    out = set()
    with open(path, encoding="utf-8") as f:
        for line in f:
            m = re.match(r"#+\s+(.*)", line)
            if m:
                a = m.group(1).strip().lower()
                a = re.sub(r"[^\w\- ]", "", a).replace(" ", "-")
                out.add(a)
    return out


for md in files:
    here = os.path.dirname(md)
    in_code = False
    with open(os.path.join(top, md), encoding="utf-8") as f:
        lines = f.readlines()
    for n, line in enumerate(lines, 1):
        if line.startswith("```"):
            in_code = not in_code
            continue
        where = f"{md}:{n}"
        if "../shared" in line or "/work/shared" in line:
            problems.append(f"{where}: points outside the repository: cite the document by its title")
        if in_code or line.startswith("    "):
            continue  # code: commands, not links
        for target in link_re.findall(line):
            if re.match(r"[a-z]+:", target):
                continue  # https:, mailto:
            path, _, anchor = target.partition("#")
            full = os.path.normpath(os.path.join(top, here, path)) if path else os.path.join(top, md)
            if not full.startswith(top):
                problems.append(f"{where}: link {target} leaves the repository")
            elif not os.path.exists(full):
                problems.append(f"{where}: link {target}: no such file")
            elif anchor and full.endswith(".md") and anchor not in anchors(full):
                problems.append(f"{where}: link {target}: no such heading")
        for path in code_re.findall(line):
            if not path.startswith(roots) or any(c in path for c in "*…$<>{}") or "..." in path:
                continue
            if not os.path.exists(os.path.join(top, path.rstrip("/").rstrip(".,:;"))):
                problems.append(f"{where}: `{path}`: no such file in the tree")

# The README stays a front door: topics go to docs/. CI's entry
# (.ci/run) runs the test command the README gives.
with open(os.path.join(top, "README.md"), encoding="utf-8") as f:
    readme = f.read()
if readme.count("\n") > 160:
    problems.append(f"README.md: {readme.count(chr(10))} lines: keep it under 160, move the topic to docs/")
if "    make check " not in readme:
    problems.append("README.md: no 'make check' command line (.ci/run runs the README's test command)")

# tests/README.md maps every source file to its tests: each file of the
# module, the engine, the library and the tools matches a pattern of its
# table's first column, and each pattern matches a file.
sources = subprocess.run(["git", "ls-files", "kmod/*.c", "kmod/*.rules", "lib/*", "tools/*"], cwd=top,
                         capture_output=True, text=True, check=True).stdout.split()
sources = [f for f in sources if not f.endswith(("CMakeLists.txt", ".md"))]
patterns, in_map = [], False
with open(os.path.join(top, "tests/README.md"), encoding="utf-8") as f:
    for n, line in enumerate(f, 1):
        if line.startswith("#"):
            in_map = line.strip() == "## Source files and their tests"
        elif in_map and line.startswith("| `"):
            patterns += [(p, n) for p in code_re.findall(line.split("|")[1])]
for src in sources:
    if not any(fnmatch.fnmatch(src, p) for p, _ in patterns):
        problems.append(f"tests/README.md: {src} is not in the map of source files to their tests")
for p, n in patterns:
    if not any(fnmatch.fnmatch(src, p) for src in sources):
        problems.append(f"tests/README.md:{n}: `{p}` names no source file")

for p in problems:
    print(p)
sys.exit(1 if problems else 0)
