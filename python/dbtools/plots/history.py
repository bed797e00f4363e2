"""Trend view of the tracking suite (experiments/track.cpp, `./run track`). Reads history files only.

  python3 -m dbtools.plots.history [--results results] [--out RESULTS/figures] [--machine ID]

Reads RESULTS/history/runs/*.csv and RESULTS/history/reference/*.csv (runs with --override rules left out), keeps
one machine's (default: the newest run's), joins the runs of one commit taken in a row on that machine (the --runs
of one `./run track`) into one point, their rounds pooled as the gate pools them, and writes for the deformation
cells, one panel per tier and a line per method / build, over the points in date order (labelled by commit), with
the machine rates of each point below:
  OUT/history_init.png          init CPU time (make_deformer: build + analyze + factorize, init_cpu_s)
  OUT/history_frame.png         frame CPU time (the median frame, frame_cpu_s)
  OUT/history_factor_bytes.png  factor bytes
  OUT/history_peak_rss.png      peak RSS of the cell's process
The times are the CPU times the gate compares (dbtools/track/gate.py), normalized as it normalizes them: each
round of a run divided by that round's drift, the median over the round's CPU times of (time / that time's
median over all the plotted runs), then the median over the run's rounds; each point's bar spans its rounds' min
to max. The rates panel (dgemm GFlop/s and memory read GB/s around the run's cells, each on its own axis) shows
whether a step is the machine's. One point is no trend: then no figure is written (and earlier ones are removed).
Run with Debian's /usr/bin/python3 (numpy + matplotlib).
"""
import csv
import os
import statistics
import sys
from collections import defaultdict
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from .bars import spread_bars  # noqa: E402
from .cli import out_dir, parser  # noqa: E402
from .styles import styles  # noqa: E402

FIGURES = [("init_cpu_s", "init CPU (s)", 1.0, "history_init.png"),
           ("frame_cpu_s", "frame CPU (ms)", 1e3, "history_frame.png"),
           ("factor_bytes", "factor (MiB)", 1 / 1048576, "history_factor_bytes.png"),
           ("peak_rss_bytes", "peak RSS (MiB)", 1 / 1048576, "history_peak_rss.png")]


def read_runs(results):
    """[rows] in date order: the rows of every history file (by file name: a reference copy of a run counts once),
    the runs of one commit in a row on one machine joined (joined())."""
    runs = {}
    for sub in ("runs", "reference"):
        for p in sorted(Path(results, "history", sub).glob("*.csv")):
            with open(p, newline="") as f:
                rows = [dict(r, history_file=p.name) for r in csv.DictReader(f)]  # run_count's run identity
            if rows and "machine_id" in rows[0] and not rows[0].get("overrides"):
                runs.setdefault(p.name, rows)
    return joined(sorted(runs.values(), key=lambda rows: rows[0]["date"]))


def joined(runs):
    """The runs (date order) with those of one commit (git_sha, "+dirty" included) taken in a row on one machine
    joined into one, the k-th one's rounds renumbered as history.pooled numbers them: one point per commit, as
    `./run track` gates them (its --runs runs a side), its spread that of all their rounds."""
    from ..track.history import pooled_round  # noqa: PLC0415
    out, last = [], {}  # last: machine -> (commit, index in out, runs joined)
    for rows in runs:
        m, commit = rows[0]["machine_id"], rows[0].get("git_sha") or rows[0]["commit"]
        if m in last and last[m][0] == commit:
            _, i, k = last[m]
            out[i] = out[i] + [dict(r, repeat=str(pooled_round(k, int(r["repeat"])))) if r["repeat"].isdigit()
                               else r for r in rows]
            last[m] = (commit, i, k + 1)
        else:
            last[m] = (commit, len(out), 1)
            out.append(rows)
    return out


def run_count(rows):
    """The history files joined into `rows`: their dates, and their file names where read_runs gave them (two runs
    of one invocation may start within the same second, the dates' resolution)."""
    return len({(r["date"], r.get("history_file", "")) for r in rows})


def summary(values):
    """(median, min, max) of a non-empty list."""
    return statistics.median(values), min(values), max(values)


def medians(rows):
    """(cell, measure) -> (median, min, max) of its values; 'dgemm' / 'read' -> those of the rate over the run."""
    vals, rates = defaultdict(list), defaultdict(list)
    for r in rows:
        if r["value"] != "":
            vals[(r["cell"], r["measure"])].append(float(r["value"]))
        for k, a, b in (("dgemm", "blas_dgemm_before", "blas_dgemm_after"),
                        ("read", "memory_read_before", "memory_read_after")):
            if r.get(a) not in (None, "", "nan"):
                rates[k].append((float(r[a]) + float(r[b])) / 2)
    out = {k: summary(v) for k, v in vals.items()}
    out.update({k: summary(v) for k, v in rates.items()})
    return out


def normalized_cpu(runs, gate):
    """[{(cell, measure): (median, min, max) of the normalized CPU times}] per run: the gate's round drift
    (gate.round_drift) against the pooled medians of every plotted run, each run's values divided by their round's
    factor."""
    s = gate.Settings()
    hists = [gate.History.from_rows(rows) for rows in runs]
    pooled = defaultdict(list)
    for h in hists:
        for key, (cls, _) in h.classes.items():
            if cls == "cpu":
                pooled[key] += [v for v in h.values[key].values() if v == v]
    ref = {k: statistics.median(v) for k, v in pooled.items()
           if len(v) >= s.min_repeats and statistics.median(v) >= s.min_time_s}
    out = []
    for h in hists:
        drift = gate.Drift(now=gate.round_drift(h, ref, s))
        out.append({key: summary(vals) for key in pooled if key in h.values
                    for vals in [drift.normalized(h, key, "now")] if vals})
    return out


def label(rows):
    r = rows[0]
    return f"{r.get('git_sha') or r['commit'][:12]}\n{r['date'][5:16].replace('T', ' ')}"


def deform_cells(runs):
    """tier -> sorted cell names of the deformation cells, tiers in the order they first appear."""
    tiers = {}
    for rows in runs:
        for r in rows:
            if r["kind"] == "deform":
                tiers.setdefault(r["tier"], set()).add(r["cell"])
    return {t: sorted(c) for t, c in tiers.items()}


def series(cell):
    """A deformation cell's line: "method build" (its tier is the panel)."""
    return " ".join(cell.split("/")[2:4])


NAN = (float("nan"),) * 3


def figure(runs, meds, measure, ylabel, scale, path):
    tiers = deform_cells(runs)
    x = list(range(len(runs)))
    fig, axes = plt.subplots(len(tiers) + 1, 1, figsize=(max(8.5, 1.1 * len(runs) + 5.5), 2.6 * (len(tiers) + 1)),
                             sharex=True, squeeze=False)
    st = styles(None, sorted({series(c) for cells in tiers.values() for c in cells}))
    for ax, (tier, cells) in zip(axes[:, 0], tiers.items()):
        for cell in cells:
            stats = [m.get((cell, measure), NAN) for m in meds]
            spread(ax, x, stats, scale, ls="-" if cell.split("/")[3] == "structured" else "--", label=series(cell),
                   **st[series(cell)])
        ax.set_title(f"{tier} (bars: min to max over the point's rounds)", fontsize=9, loc="left")
        ax.set_ylabel(ylabel)
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1))
        ax.grid(alpha=0.3)
    rates_panel(axes[-1, 0], x, meds)
    axes[-1, 0].set_xticks(x)
    axes[-1, 0].set_xticklabels([label(r) for r in runs], fontsize=7, rotation=45, ha="right")
    what = ", normalized by the rounds' drift" if measure.endswith("_cpu_s") else ""
    fig.suptitle(f"tracking suite: {ylabel} per cell over runs{what} (machine {runs[-1][0]['machine_id']})",
                 fontsize=10)
    fig.tight_layout()
    tmp = f"{path}.tmp.{os.getpid()}.png"
    fig.savefig(tmp, dpi=110)
    plt.close(fig)
    os.replace(tmp, path)


def spread(ax, x, stats, scale, **style):
    """A line through the medians, each point's bar from its min to its max."""
    spread_bars(ax, x, *([v[i] * scale for v in stats] for i in range(3)), capsize=3, **style)


def rates_panel(ax, x, meds):
    """The machine rates, each on its own axis (GFlop/s left, GB/s right), in its axis' colour."""
    st = styles(None, ["dgemm GFlop/s", "memory read GB/s"])
    twin = ax.twinx()
    for a, key, name in ((ax, "dgemm", "dgemm GFlop/s"), (twin, "read", "memory read GB/s")):
        spread(a, x, [m.get(key, NAN) for m in meds], 1.0, label=name, **st[name])
        a.set_ylabel(name, color=st[name]["color"], fontsize=8)
        a.tick_params(axis="y", colors=st[name]["color"])
    ax.set_title("machine rates around the cells (medians; bars: min to max)", fontsize=9, loc="left")
    ax.grid(alpha=0.3)


def plot(results, out, machine=None):
    """The trend figures of one machine's runs (default: the newest run's machine); 0 drawn or nothing to draw, 1 no
    run of that machine, 2 a history the gate refuses."""
    runs = read_runs(results)
    if not runs:
        print(f"history: no history under {results}/history: skipped", file=sys.stderr)
        return 0
    from ..track import gate  # noqa: PLC0415 - the gate's rules (round drift), needed only when there is history
    machine = machine or runs[-1][0]["machine_id"]
    runs = [r for r in runs if r[0]["machine_id"] == machine]
    if not runs:
        print(f"history: no history of machine {machine}", file=sys.stderr)
        return 1
    if len(runs) < 2:  # one point is no trend: its values are in the run's CSV and the site's history pages
        for _, _, _, name in FIGURES:
            Path(out, name).unlink(missing_ok=True)
        print(f"history: one point of machine {machine} (the runs of one commit in a row join): no trend figure "
              "until a run of another commit (./run track)", file=sys.stderr)
        return 0
    meds = [medians(r) for r in runs]
    try:
        for m, cpu in zip(meds, normalized_cpu(runs, gate)):
            m.update(cpu)
    except gate.InputError as e:
        print(f"history: {e}", file=sys.stderr)
        return 2
    os.makedirs(out, exist_ok=True)
    for measure, ylabel, scale, name in FIGURES:
        figure(runs, meds, measure, ylabel, scale, os.path.join(out, name))
    print(f"history: {sum(map(run_count, runs))} run(s) of machine {machine} as {len(runs)} point(s) (the runs of "
          f"one commit in a row joined) -> {out}/history_*.png", file=sys.stderr)
    return 0


def main(argv=None):
    ap = parser(__doc__)
    ap.add_argument("--machine", help="machine id (default: the newest run's)")
    try:
        a = ap.parse_args(argv)
    except SystemExit as e:  # argparse's usage error is 2; the project's is 1
        return 1 if e.code == 2 else e.code
    return plot(a.results, out_dir(a), a.machine)


if __name__ == "__main__":
    sys.exit(main())
