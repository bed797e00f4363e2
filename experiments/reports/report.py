#!/usr/bin/python3
"""The report step: the Markdown reports from the CSVs the experiment drivers wrote (measuring apart from
reporting: nothing here measures, and a report can be rewritten after editing this code without rerunning a cell).

  experiments/reports/report.py [--results DIR] [--only table_2_1,solvers,frames]

Writes RESULTS/table_2_1.md, solvers.md and frames.md, each only when its CSV exists. Standard library only; ./run
runs it with /usr/bin/python3 like the plots.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import frames  # noqa: E402
import solvers  # noqa: E402
import table_2_1  # noqa: E402

REPORTS = {"table_2_1": table_2_1.write, "solvers": solvers.write, "frames": frames.write}


def main():
    ap = argparse.ArgumentParser(description="Markdown reports from the experiment CSVs")
    ap.add_argument("--results", default="results", help="directory of the CSVs (and of the reports)")
    ap.add_argument("--only", default=",".join(REPORTS), help="comma-separated: " + ", ".join(REPORTS))
    a = ap.parse_args()
    if not os.path.isdir(a.results):
        print(f"report: error: --results {a.results}: not a directory", file=sys.stderr)
        return 1
    names = [n for n in a.only.split(",") if n]
    unknown = [n for n in names if n not in REPORTS]
    if unknown:
        print(f"report: error: --only: unknown report(s) {unknown} (known: {', '.join(REPORTS)})", file=sys.stderr)
        return 1
    for n in names:
        wrote = REPORTS[n](a.results)
        print(f"[report] {n}.md: " + ("written" if wrote else f"no {n}.csv, skipped"), file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
