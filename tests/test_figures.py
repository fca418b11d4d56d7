#!/usr/bin/python3
"""The figures are ready for a paper (issue 25): with `[Report] figure_format = png,pdf,svg`, run's
map and compare's comparison figure, and the sweep's plots with `--figure-format png,pdf`, come as
PNG at 300 dpi and as vector PDF and SVG, one paper column (3.5 in = 252 pt) or two (7.16 in =
516 pt) wide. Headless: every PDF opens and renders (poppler's `pdftoppm`), and its text
(`pdftotext`) holds every legend entry; every SVG is XML of the same size with its text as <text> elements; every PNG is 300 dpi.

    test_figures.py --source SOURCE_DIR --build BUILD_DIR [unittest options]
"""
import argparse
import glob
import os
import re
import struct
import subprocess
import sys
import tempfile
import unittest
import xml.etree.ElementTree as ET

SOURCE = BUILD = None


def pdf_text(path):
    p = subprocess.run(["pdftotext", path, "-"], capture_output=True, text=True, check=True)
    return " ".join(p.stdout.split())


def pdf_width_pt(path):
    p = subprocess.run(["pdfinfo", path], capture_output=True, text=True, check=True)
    m = re.search(r"Page size:\s+([\d.]+) x ([\d.]+) pts", p.stdout)
    return float(m.group(1))


def png_width(path):
    with open(path, "rb") as f:
        head = f.read(24)
    assert head[:8] == b"\x89PNG\r\n\x1a\n", path
    return struct.unpack(">I", head[16:20])[0]


def svg_width(path):
    root = ET.parse(path).getroot()
    return root.get("width")


def svg_text(path):
    """The text of the SVG's <text> elements, joined as pdftotext joins a PDF's."""
    root = ET.parse(path).getroot()
    return " ".join(" ".join(t.text or "" for t in root.iter("{http://www.w3.org/2000/svg}text")).split())


class PaperFigures(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="test_figures_")
        t = cls.tmp.name
        bin_ = os.path.join(BUILD, "bin", "budget-slam")
        config, demo = os.path.join(SOURCE, "config.ini"), os.path.join(SOURCE, "rawlogs", "kf-slam_demo.rawlog")
        vector = ["--set", "Report.figure_format=png,pdf,svg", "--quiet"]
        cls.run_dir, cls.cmp_dir, cls.sweep_dir = (os.path.join(t, n) for n in ("run", "cmp", "sweep"))
        cls.procs = [
            subprocess.run([bin_, "run", "-c", config, "-i", demo, "-o", cls.run_dir, "--cap", "20"] + vector,
                           capture_output=True, text=True, timeout=300),
            subprocess.run([bin_, "compare", "-c", config, "-i", demo, "-o", cls.cmp_dir, "--cap", "20",
                            "--reducers", "mi,coverage"] + vector, capture_output=True, text=True, timeout=300),
            subprocess.run(["/usr/bin/python3", os.path.join(SOURCE, "tools", "experiments", "sweep"),
                            os.path.join(SOURCE, "tools", "experiments", "experiments", "tiny.ini"), "-o",
                            cls.sweep_dir, "-q", "-j", "2", "--figure-format", "png,pdf",
                            "--budget-slam", bin_], capture_output=True, text=True, timeout=600)]

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def renders(self, pdf):
        out = os.path.join(self.tmp.name, "render")
        p = subprocess.run(["pdftoppm", "-r", "36", "-png", "-singlefile", pdf, out], capture_output=True, text=True)
        self.assertEqual(p.returncode, 0, f"{pdf}: {p.stderr}")
        self.assertGreater(os.path.getsize(out + ".png"), 1000, pdf)
        self.assertEqual(p.stderr, "", pdf)  # poppler says nothing wrong about the file

    def test_commands_ran(self):
        for p in self.procs:
            self.assertEqual(p.returncode, 0, p.stderr)

    def test_map_in_three_formats_one_column_wide_with_every_legend_entry(self):
        stem = os.path.join(self.run_dir, "map")
        self.assertEqual(png_width(stem + ".png"), 1050)  # 3.5 in at 300 dpi
        self.assertEqual(svg_width(stem + ".svg"), "252pt")
        self.renders(stem + ".pdf")
        self.assertEqual(pdf_width_pt(stem + ".pdf"), 252)
        text = pdf_text(stem + ".pdf")
        for entry in ["kf-slam_demo.rawlog: ekf, reducer localization-information, cap 20: 20 landmarks kept,",
                      "path, >= 4 map landmarks in view (", "path, 2 to 3 in view (",
                      "path, < 2 in view: cannot relocalize (", "ground-truth path", "ground-truth landmark",
                      "kept landmark, 2-sigma ellipse, colour: coverage cluster", "dropped landmark",
                      "x [m]", "y [m]"]:
            self.assertIn(entry, text)
            self.assertIn(entry, svg_text(stem + ".svg"))  # text as text in the SVG too

    def test_comparison_two_columns_wide_with_every_run_and_the_cap(self):
        stem = os.path.join(self.cmp_dir, "comparison")
        self.assertEqual(png_width(stem + ".png"), 2150)  # 7.16 in at 300 dpi
        self.assertEqual(svg_width(stem + ".svg"), "516pt")
        self.renders(stem + ".pdf")
        self.assertEqual(pdf_width_pt(stem + ".pdf"), 516)
        text = pdf_text(stem + ".pdf")
        self.assertIn("compare: kf-slam_demo.rawlog, backend ekf, cap 20, 249 steps, seed 1", text)
        self.assertIn("landmarks in the map [landmarks]", text)
        self.assertIn("robot position error against ground truth (online estimate) [m]", text)
        self.assertIn("cap 20", text)
        # every run in the legend of both panels
        for run in ("reference", "mi", "coverage"):
            self.assertEqual(len(re.findall(rf"(?<![\w-]){re.escape(run)}(?![\w-])", text)), 2, run)
        # and each run's own map too
        for run in ("reference", "mi", "coverage"):
            self.renders(os.path.join(self.cmp_dir, run, "map.pdf"))

    def test_sweep_plots_as_pdf_with_their_legends(self):
        pdfs = sorted(glob.glob(os.path.join(self.sweep_dir, "plots", "*.pdf")))
        self.assertEqual(len(pdfs), 7)
        for pdf in pdfs:
            self.renders(pdf)
            self.assertEqual(os.path.getsize(pdf[:-4] + ".png") > 0, True)
            width = pdf_width_pt(pdf)
            self.assertIn(round(width), (252, 516), pdf)  # 3.5 in, or 7.16 in for two panels
            text = pdf_text(pdf)
            if pdf.endswith("__step_time.pdf") or pdf.endswith("__landmarks.pdf"):
                for name in ("none", "coverage", "mi"):
                    self.assertIn(name, text.split(), pdf)
            if pdf.endswith("error_vs_cap.pdf"):
                for entry in ("none", "coverage", "mi", "cap [landmarks]", "(=35)"):
                    self.assertIn(entry, text, pdf)
            self.assertNotIn("Type 3", subprocess.run(["pdffonts", pdf], capture_output=True, text=True).stdout, pdf)


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--source", required=True)
    ap.add_argument("--build", required=True)
    args, rest = ap.parse_known_args()
    SOURCE, BUILD = os.path.abspath(args.source), os.path.abspath(args.build)
    unittest.main(argv=[sys.argv[0]] + rest)
