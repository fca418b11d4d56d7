#!/usr/bin/python3
"""Every documentation reference in the source tree resolves inside the tree.

    tools/check_doc_references.py [SOURCE_DIR]

Scans the tracked files (`git ls-files`; without git, every file outside build folders) for
  - the name of the external design contract, which is not part of the tree (its rules live in
    docs/ARCHITECTURE.md);
  - paths under docs/ (`docs/GRAPH.md`, `docs/results/lifelong.png`, globs such as `docs/results/*.png`)
    that name no file or folder;
  - relative Markdown links in .md files (`[text](GRAPH.md)`) whose target is missing;
  - bare names of Markdown pages (`OUTPUTS.md`) that are neither at the top level nor in docs/.
Prints one line a bad reference (`file:line: what`) and exits 1 when there is any, else 0.
"""
import glob
import os
import re
import subprocess
import sys

# Spelled in two pieces so that this file does not trip its own check.
EXTERNAL_CONTRACT = "DESIGN" + ".md"

DOCS_PATH = re.compile(r"docs/[A-Za-z0-9_./*-]*")
MD_LINK = re.compile(r"\]\(([^)\s#]+)(?:#[^)]*)?\)")
BARE_PAGE = re.compile(r"(?<![\w/.-])([A-Z][A-Z0-9_]*\.md)\b")
# The checker's own test writes made-up trees full of bad references on purpose.
SKIP_FILES = {"tools/tests/test_check_doc_references.py"}
SKIP_DIRS = {".git", "build", "build-asan", "build-fuzz", "__pycache__"}
TEXT_SUFFIXES = (".md", ".txt", ".h", ".hpp", ".cpp", ".py", ".sh", ".ini", ".cmake", ".yml",
                 ".yaml", ".json", ".in")


def git(root, *args):
    return subprocess.run(["git", "-C", root, *args], check=True, capture_output=True).stdout


def tracked_files(root):
    """The files git tracks when `root` is the top of a git work tree, else every file."""
    try:
        top = git(root, "rev-parse", "--show-toplevel").decode().strip()
        if os.path.realpath(top) == os.path.realpath(root):
            return [f for f in git(root, "ls-files", "-z").decode().split("\0") if f]
    except (OSError, subprocess.CalledProcessError):
        pass
    files = []
    for d, dirs, names in os.walk(root):
        dirs[:] = [x for x in dirs if x not in SKIP_DIRS and not x.startswith("build")]
        files += [os.path.relpath(os.path.join(d, n), root) for n in names]
    return files


def is_text(rel):
    base = os.path.basename(rel)
    return (rel.endswith(TEXT_SUFFIXES) or base in ("CMakeLists.txt", "run") or
            rel.startswith("tools/") and "." not in base)


def exists(root, rel_path):
    rel_path = rel_path.rstrip(".,;:")
    if "*" in rel_path:
        return bool(glob.glob(os.path.join(root, rel_path)))
    return os.path.exists(os.path.join(root, rel_path))


def problems(root, rel):
    path = os.path.join(root, rel)
    try:
        with open(path, encoding="utf-8") as f:
            lines = f.read().splitlines()
    except (UnicodeDecodeError, OSError):
        return []
    out = []
    for n, line in enumerate(lines, start=1):
        where = f"{rel}:{n}"
        if EXTERNAL_CONTRACT in line:
            out.append(f"{where}: names {EXTERNAL_CONTRACT}, which is not in the tree")
        for m in DOCS_PATH.finditer(line):
            target = m.group(0).rstrip(".,;:")
            if target != "docs/" and not exists(root, target):
                out.append(f"{where}: {target} does not exist")
        if rel.endswith(".md"):
            for m in MD_LINK.finditer(line):
                target = m.group(1)
                if "://" in target or target.startswith("mailto:"):
                    continue
                if not exists(root, os.path.join(os.path.dirname(rel), target)):
                    out.append(f"{where}: link {target} does not exist")
        for m in BARE_PAGE.finditer(line):
            page = m.group(1)
            if page == EXTERNAL_CONTRACT:
                continue  # reported above
            if not (exists(root, page) or exists(root, "docs/" + page)):
                out.append(f"{where}: {page} is neither at the top level nor in docs/")
    return out


def main(argv):
    root = os.path.abspath(argv[1] if len(argv) > 1 else
                           os.path.join(os.path.dirname(__file__), ".."))
    bad = []
    for rel in tracked_files(root):
        if rel not in SKIP_FILES and is_text(rel) and os.path.isfile(os.path.join(root, rel)):
            bad += problems(root, rel)
    for b in bad:
        print(b)
    if bad:
        print(f"{len(bad)} unresolved documentation reference(s)")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
