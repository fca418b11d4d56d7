#!/usr/bin/python3
"""tools/check_doc_references.py finds each kind of unresolved reference, and only those."""
import os
import subprocess
import sys
import tempfile
import unittest

CHECKER = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..",
                       "check_doc_references.py")


def write(root, rel, text):
    path = os.path.join(root, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(text)


def check(root):
    r = subprocess.run([sys.executable, CHECKER, root], capture_output=True, text=True)
    return r.returncode, r.stdout.splitlines()


class CheckDocReferences(unittest.TestCase):
    def tree(self):
        d = tempfile.TemporaryDirectory()
        self.addCleanup(d.cleanup)
        write(d.name, "README.md", "See docs/GUIDE.md and docs/pics/*.png.\n")
        write(d.name, "docs/GUIDE.md", "Formulas: [the map](pics/map.png), OUTPUTS.md.\n")
        write(d.name, "docs/OUTPUTS.md", "Columns.\n")
        write(d.name, "docs/pics/map.png", "")
        write(d.name, "src/a.cpp", "// (docs/GUIDE.md \"Formulas\")\nint x;\n")
        return d.name

    def test_a_tree_whose_references_resolve_passes(self):
        self.assertEqual(check(self.tree()), (0, []))

    def test_each_kind_of_bad_reference_is_reported_with_its_line(self):
        root = self.tree()
        write(root, "src/b.h", "int y;\n// see " + "DESIGN" + ".md \"Outputs\"\n")
        write(root, "src/c.cpp", "// docs/GONE.md\n")
        write(root, "docs/LINKS.md", "[x](MISSING.md) and [web](https://example.org/a.md)\n")
        write(root, "tools/run.sh", "cat RESULTS.md\n")
        code, lines = check(root)
        self.assertEqual(code, 1)
        self.assertIn("src/b.h:2: names " + "DESIGN" + ".md, which is not in the tree", lines)
        self.assertIn("src/c.cpp:1: docs/GONE.md does not exist", lines)
        self.assertIn("docs/LINKS.md:1: link MISSING.md does not exist", lines)
        self.assertIn("tools/run.sh:1: RESULTS.md is neither at the top level nor in docs/", lines)
        self.assertEqual(lines[-1], "5 unresolved documentation reference(s)")


if __name__ == "__main__":
    unittest.main()
