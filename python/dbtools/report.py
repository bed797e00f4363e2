"""The report step, the one step after the drivers: every figure, then every Markdown report, from the CSVs the
drivers wrote under the results directory. Nothing here measures: a report or figure can be rewritten after
editing its code without rerunning a cell.

  python3 -m dbtools.report [--results DIR] [--only NAME,...]     (PYTHONPATH=<repo>/python; Debian's python3)

Per experiment (EXPERIMENTS below, named after its driver): its figures go to RESULTS/figures/ (dbtools/plots/NAME.py
and friends), then its reports to RESULTS/NAME.md (dbtools/reports/NAME.py and friends), each only when its CSV
exists. The figures are all drawn before the first report, since reports cite them and say which are missing. A
figure module that fails does not stop the others or the reports; the step then exits 1, naming it. Last, the static
site RESULTS/site/index.html (dbtools/site/) shows the reports, their figures, the tracking history and the
deformed meshes in a browser.
"""
import argparse
import importlib
import os
import sys
import traceback

from .reports import applications, figures, frames, handle_frames, predictions, solvers, table_2_1
from .reports.common import figures_dir

# experiment -> ([its figure modules under dbtools/plots/], [(report, its CSV, write)]). A figure module's
# plot(results, out) draws into out; it is imported when drawn, so one that cannot load (numpy, matplotlib, the
# tracking gate) fails alone. A report's write(results) writes RESULTS/REPORT.md and says whether its CSV was there.
EXPERIMENTS = {
    "table_2_1": (["table_2_1"], [("table_2_1", "table_2_1", table_2_1.write)]),
    "solvers": (["solvers"], [("solvers", "solvers", solvers.write)]),
    "frames": (["frames", "render_meshes"], [("frames", "frames", frames.write), ("figures", "frames", figures.write)]),
    "applications": (["applications"], [("applications", "applications", applications.write)]),
    "handle_frames": ([], [("handle_frames", "handle_frames", handle_frames.write_frames),
                           ("handle_drags", "handle_drags", handle_frames.write_drags)]),
    "predictions": (["predictions"], [("predictions", "predictions", predictions.write)]),
    "history": (["history"], []),  # the tracking suite's trend view (./run track writes the history)
}


def log(text):
    print(f"[report] {text}", file=sys.stderr)


def draw_figures(results, names):
    """Every figure module of the named experiments; the names of those that failed."""
    failed = []
    for name in names:
        for label in EXPERIMENTS[name][0]:
            try:
                rc = importlib.import_module(f".plots.{label}", __package__).plot(results, figures_dir(results))
            except Exception:  # noqa: BLE001 - one broken figure must not cost the other figures and the reports
                traceback.print_exc()
                rc = "an exception"
            if rc:
                log(f"figures of {label} failed ({rc if isinstance(rc, str) else 'exit ' + str(rc)})")
                failed.append(label)
    return failed


def write_reports(results, names):
    for name in names:
        for report, csv_name, write in EXPERIMENTS[name][1]:
            log(f"{report}.md: " + ("written" if write(results) else f"no {csv_name}.csv, skipped"))


def write_site(results):
    """The static site (dbtools/site/), last: it shows the reports and figures. Whether it was written."""
    try:
        from . import site
        site.write(results)
        return True
    except Exception:  # noqa: BLE001 - the reports stand without the site; the step then fails, naming it
        traceback.print_exc()
        log("error: the site (dbtools.site) failed: see above")
        return False


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python3 -m dbtools.report", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--results", default="results", help="directory of the CSVs, the reports and figures/")
    ap.add_argument("--only", default=",".join(EXPERIMENTS), help="comma-separated: " + ", ".join(EXPERIMENTS))
    a = ap.parse_args(argv)
    names = [n for n in a.only.split(",") if n]
    unknown = [n for n in names if n not in EXPERIMENTS]
    if unknown:
        print(f"report: error: --only: unknown experiment(s) {unknown} (known: {', '.join(EXPERIMENTS)})",
              file=sys.stderr)
        return 1
    if not os.path.isdir(a.results):
        print(f"report: error: --results {a.results}: not a directory", file=sys.stderr)
        return 1
    failed = draw_figures(a.results, names)
    write_reports(a.results, names)
    site_ok = write_site(a.results)
    if failed:
        log(f"error: figures failed: {', '.join(failed)} (the reports say which figures are missing)")
    return 0 if site_ok and not failed else 1


if __name__ == "__main__":
    sys.exit(main())
