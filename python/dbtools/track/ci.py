"""A run of a suite as github-action-benchmark's `customSmallerIsBetter` input: a JSON list of
{"name", "unit", "value", "range", "extra"}, one entry per gated measure of every cell that ran (docs/tracking.md
shows the CI workflow that reads it). Written by `./run track` beside each run's history CSV (runs/STEM.json) and
as RESULTS/history/latest.json (the newest invocation's runs, --runs of them, pooled as the gate pools them: a
fixed path for CI, one entry per measure whatever the number of runs).

  python3 -m dbtools.track.ci HISTORY... [--out JSON]    (history CSVs or bench_phases JSONs; several: pooled)

value: the median over the run's rounds (of all the runs pooled); range: "± half the min-max spread" of the rounds
(absent with one round); extra: the gate's class, the rounds (and runs), min and max, commit and machine. Every
measure here is smaller-is-better
(times, bytes, counts); class "info" (recorded, never compared) and failed cells are left out: the gate's verdict,
not this file, is what fails a build.
"""
import argparse
import json
import math
import os
import statistics
import sys

from .history import InputError, load_runs

GATED = ("deterministic", "memory", "cpu", "time")


def unit(measure):
    if measure.endswith("_s"):
        return "s"
    return "bytes" if measure.endswith("bytes") else "count"


def entries(h):
    """The benchmark entries of the record `h`, sorted by name."""
    out = []
    sha = h.meta.get("git_sha") or h.meta.get("commit", "")[:12]
    for (cell, measure), reps in sorted(h.values.items()):
        cls = h.classes[(cell, measure)][0]
        vals = [v for v in reps.values() if not math.isnan(v)]
        if cls not in GATED or cell in h.failed or not vals:
            continue
        e = {"name": f"{cell} {measure}", "unit": unit(measure), "value": statistics.median(vals)}
        if len(vals) > 1:
            e["range"] = f"± {(max(vals) - min(vals)) / 2:.4g}"
        runs = f" of {h.runs} runs" if h.runs > 1 else ""
        e["extra"] = (f"class {cls}; {len(vals)} round(s){runs}, min {min(vals):.6g}, max {max(vals):.6g}; "
                      f"commit {sha}; machine {h.meta.get('machine_id', '')}")
        out.append(e)
    return out


def document(history_paths):
    """The JSON of a history (a path) or of several runs of one commit (a list of paths, pooled)."""
    return json.dumps(entries(load_runs(history_paths)), indent=1) + "\n"


def _write(path, doc):
    tmp = f"{path}.tmp.{os.getpid()}"
    with open(tmp, "w") as f:
        f.write(doc)
    os.replace(tmp, path)


def write(history_paths, latest=None):
    """Writes STEM.json beside each history CSV of `history_paths` (the runs of one invocation) and, when given,
    the runs pooled to `latest`; the paths of the JSONs beside the CSVs."""
    history_paths = [str(p) for p in history_paths]
    if not all(p.endswith(".csv") for p in history_paths):
        raise ValueError(f"{', '.join(history_paths)}: not history CSVs")
    out = []
    for p in history_paths:
        out.append(p[:-len(".csv")] + ".json")
        _write(out[-1], document(p))
    if latest:
        _write(str(latest), document(history_paths))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python3 -m dbtools.track.ci", description=__doc__.split("\n")[0])
    ap.add_argument("history", nargs="+", help="a record, or several runs of one commit (pooled)")
    ap.add_argument("--out", help="write here instead of stdout")
    a = ap.parse_args(argv)
    try:
        doc = document(a.history)
    except InputError as e:
        print(f"ci: error: {e}", file=sys.stderr)
        return 2
    if a.out:
        with open(a.out, "w") as f:
            f.write(doc)
    else:
        sys.stdout.write(doc)
    return 0


if __name__ == "__main__":
    sys.exit(main())
