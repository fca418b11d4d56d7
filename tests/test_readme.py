#!/usr/bin/python3
"""Every command block of README.md (```bash) runs as printed, in order, from a copy of the
repository's top folder: each block is one `bash -e -o pipefail` script, run in a fresh folder
whose entries are the tracked top-level files and folders of the source tree (symbolic links) and
`build`, the build folder. A block passes when it exits 0, prints no warning or error line, and
every output folder a `budget-slam` command of it names (`-o DIR`) holds a summary.json with
status ok; after the last block, nothing was written beside the tracked entries but `out/`, which
git ignores. The README can therefore never show a command that does not run, nor one that leaves
`git status` unclean.

`tools/test.sh` in the README runs the whole suite; inside the suite (BUDGET_SLAM_IN_SUITE=1) it
lists the tests instead of running them again.

    test_readme.py --source SOURCE_DIR --build BUILD_DIR [unittest options]
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import unittest

SOURCE = BUILD = None


def command_blocks(readme):
    """The ```bash blocks of the README, in order, as printed."""
    return re.findall(r"^```bash\n(.*?)^```", readme, re.M | re.S)


def commands(block):
    """The block's commands with backslash continuations joined, comments and blank lines left out."""
    joined = re.sub(r"\s*\\\n\s*", " ", block)
    return [l.strip() for l in joined.splitlines() if l.strip() and not l.strip().startswith("#")]


def tracked_top_level(root):
    """The top-level names git tracks in `root` (every name but build folders without git)."""
    try:
        files = subprocess.run(["git", "-C", root, "ls-files"], check=True, capture_output=True,
                               text=True).stdout.split()
        return sorted({f.split("/", 1)[0] for f in files})
    except (OSError, subprocess.CalledProcessError):
        return sorted(n for n in os.listdir(root) if not n.startswith(("build", ".git", "OUT")))


class ParsingTheReadme(unittest.TestCase):
    def test_blocks_and_continuations(self):
        text = "x\n```bash\na --b \\\n    c   # d\n# comment\n\ne\n```\n```python\nno\n```\n```bash\nf\n```\n"
        blocks = command_blocks(text)
        self.assertEqual(len(blocks), 2)
        self.assertEqual(commands(blocks[0]), ["a --b c   # d", "e"])
        self.assertEqual(commands(blocks[1]), ["f"])


class ReadmeRunsAsPrinted(unittest.TestCase):
    def test_every_block_in_order(self):
        with open(os.path.join(SOURCE, "README.md")) as f:
            blocks = command_blocks(f.read())
        self.assertGreaterEqual(len(blocks), 2)
        with tempfile.TemporaryDirectory(prefix="test_readme_") as work:
            for name in tracked_top_level(SOURCE):
                if name != "build":
                    os.symlink(os.path.join(SOURCE, name), os.path.join(work, name))
            os.symlink(BUILD, os.path.join(work, "build"))
            env = dict(os.environ, BUDGET_SLAM_IN_SUITE="1")
            for i, block in enumerate(blocks, 1):
                with self.subTest(block=i):
                    p = subprocess.run(["bash", "-e", "-o", "pipefail", "-c", block], cwd=work, env=env,
                                       capture_output=True, text=True, timeout=900)
                    where = f"README block {i}:\n{block}\nstdout:\n{p.stdout[-3000:]}\nstderr:\n{p.stderr[-3000:]}"
                    self.assertEqual(p.returncode, 0, where)
                    bad = [l for l in p.stderr.splitlines() if re.search(r"\b(warning|error)\b", l, re.I)]
                    self.assertEqual(bad, [], where)
                    for c in commands(block):
                        m = re.match(r"build/bin/budget-slam (run|compare|localize) .*-o (\S+)", c)
                        if not m:
                            continue
                        with open(os.path.join(work, m.group(2), "summary.json")) as f:
                            self.assertEqual(json.load(f)["status"], "ok", c)
            # Everything the blocks wrote is under out/ (git ignores it): `git status` stays clean.
            made = sorted(set(os.listdir(work)) - set(tracked_top_level(SOURCE)) - {"build", "out"})
            self.assertEqual(made, [], "the README's commands wrote outside out/")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--source", required=True)
    ap.add_argument("--build", required=True)
    args, rest = ap.parse_known_args()
    SOURCE, BUILD = os.path.abspath(args.source), os.path.abspath(args.build)
    unittest.main(argv=[sys.argv[0]] + rest)
