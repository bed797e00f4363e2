#!/usr/bin/python3
"""The report step: the Markdown reports from the CSVs the experiment drivers wrote (measuring apart from
reporting: nothing here measures, and a report can be rewritten after editing this code without rerunning a cell).

  experiments/reports/report.py [--results DIR] [--plots DIR] [--only table_2_1,solvers,frames,applications,figures]

Writes RESULTS/table_2_1.md, solvers.md, frames.md, applications.md and figures.md, each only when its CSV exists
(figures.md: the thesis' figures mapped to the frames study's renders). applications.md and figures.md cite the
renders under --plots (default: the results directory's sibling plots/) and say which are missing, so ./run runs
this step once, after the plots. Standard library only; ./run runs it with /usr/bin/python3 like the plots.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import applications  # noqa: E402
import figures  # noqa: E402
import frames  # noqa: E402
import solvers  # noqa: E402
import table_2_1  # noqa: E402

REPORTS = {"table_2_1": table_2_1.write, "solvers": solvers.write, "frames": frames.write,
           "applications": applications.write, "figures": figures.write}
CSV_OF = {"figures": "frames"}  # a report named after no CSV of its own
CITES_PLOTS = {"applications", "figures"}  # reports that take the plots directory


def main():
    ap = argparse.ArgumentParser(description="Markdown reports from the experiment CSVs")
    ap.add_argument("--results", default="results", help="directory of the CSVs (and of the reports)")
    ap.add_argument("--plots", default=None, help="directory of the figures the reports cite (default: "
                    "RESULTS/../plots)")
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
        wrote = REPORTS[n](a.results, a.plots) if n in CITES_PLOTS else REPORTS[n](a.results)
        print(f"[report] {n}.md: " + ("written" if wrote else f"no {CSV_OF.get(n, n)}.csv, skipped"), file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
