"""The command line every figure module shares: --results (the CSVs) and --out (default RESULTS/figures)."""
import argparse

from ..reports.common import figures_dir


def parser(doc):
    """An ArgumentParser with --results and --out; add a module's own options to it."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--results", default="results", help="the directory of the drivers' CSVs (default: results)")
    ap.add_argument("--out", default=None, help="where the figures go (default: RESULTS/figures)")
    return ap


def out_dir(args):
    """--out, or the results directory's figures folder."""
    return args.out or figures_dir(args.results)
