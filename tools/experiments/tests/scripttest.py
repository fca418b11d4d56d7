"""What the tests of the experiment scripts share: the folders, loading a script that has no .py
name as a module, and the --budget-slam / --budget-simulate arguments that ctest passes."""
import argparse
import importlib.machinery
import importlib.util
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
EXP = os.path.dirname(HERE)
ROOT = os.path.dirname(os.path.dirname(EXP))
sys.path.insert(0, EXP)


def load_script(name):
    """tools/experiments/<name> (e.g. paper_tables) imported as a module."""
    loader = importlib.machinery.SourceFileLoader(name, os.path.join(EXP, name))
    spec = importlib.util.spec_from_loader(name, loader)
    mod = importlib.util.module_from_spec(spec)
    loader.exec_module(mod)
    return mod


def parse_binaries(doc):
    """(budget_slam, budget_simulate, remaining argv for unittest) from the command line; the
    binaries default to build/bin/."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--budget-slam", default=os.path.join(ROOT, "build", "bin", "budget-slam"))
    ap.add_argument("--budget-simulate", default=os.path.join(ROOT, "build", "bin", "budget-simulate"))
    args, rest = ap.parse_known_args()
    return os.path.abspath(args.budget_slam), os.path.abspath(args.budget_simulate), [sys.argv[0]] + rest
