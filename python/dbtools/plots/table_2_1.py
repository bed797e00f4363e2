"""Plots of thesis Table 2-1 (experiments/table_2_1.cpp). Reads CSVs only, never recomputes a measurement.

  drawn by the report step: python3 -m dbtools.report --only table_2_1 (figures into RESULTS/figures)

Reads RESULTS/table_2_1.csv, table_2_1_thesis.csv, scaling.csv and scaling_fits.csv and writes
  OUT/table_2_1_memory.png  peak RSS per cell against #V, log-log, the thesis' TF memory before / after overlaid;
                            cells not run (over the memory or time budget) at their predicted bytes, hollow, in a
                            panel of their own above, so that only measured values set the main panel's axes
  OUT/table_2_1_init.png    init time (build + analyze + factorize) against #V, thesis points overlaid; predicted
                            init times of cells not run likewise apart
  OUT/scaling.png           structured build: init, factor bytes and frame time against #V with the fitted
                            power laws (exponents from scaling_fits.csv; a fit on fewer than MIN_FIT_POINTS
                            points is not drawn), each fit's n beside its r^2
Every series has its own colour and marker (styles.py). Run with Debian's /usr/bin/python3 (numpy +
matplotlib).
"""
import csv
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from .bars import spread_bars  # noqa: E402
from .styles import styles  # noqa: E402

MIB = 1024.0 * 1024.0
BUILDS = ("structured", "naive", "dense")
SYSTEM_LINE = {"tf": "-", "lap": "--"}
# The fewest points a power law is fitted to (experiments/table_2_1.cpp writes no fit on fewer; a fit of an older
# CSV on fewer is not drawn).
MIN_FIT_POINTS = 4


def read_rows(path):
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def cells(rows, extra_key=()):
    """(model, system, build, *extra) -> {"status", "vertices", measure: value}."""
    out = defaultdict(dict)
    for r in rows:
        key = (r["model"], r["system"], r["build"]) + tuple(r[k] for k in extra_key)
        c = out[key]
        c["status"] = r["status"]
        c["storage"] = r.get("factor_storage", "memory")
        if r["vertices"]:
            c["vertices"] = float(r["vertices"])
        if r["value"] != "":
            c[r["measure"]] = float(r["value"])
    return out


def thesis_points(rows, measure):
    """stage -> [(vertices, value)] for the thesis rows that have a value (#over rows have none)."""
    pts = defaultdict(list)
    for r in rows:
        if r["measure"] == measure and r["value"] != "":
            pts[r["stage"]].append((float(r["vertices"]), float(r["value"])))
    return pts


def series_points(table, system, build, measure, scale, statuses):
    return sorted((c["vertices"], c[measure] / scale) for k, c in table.items()
                  if k[1] == system and k[2] == build and c["status"] in statuses and measure in c
                  and "vertices" in c)


def plot_builds(ax, pred_ax, table, measure, scale, predicted_measure):
    """Measured cells on ax; cells not run, at their prediction, hollow on pred_ax. Returns (whether anything was
    predicted, the styles)."""
    st = styles("table_2_1", [f"{s} {b}" for s in SYSTEM_LINE for b in BUILDS] +
                ["thesis tf before", "thesis tf after"])
    predicted = False
    for system in SYSTEM_LINE:
        for build in BUILDS:
            name = f"{system} {build}"
            ok = series_points(table, system, build, measure, scale, ("ok",))
            if ok:
                xs, ys = zip(*ok)
                ax.plot(xs, ys, SYSTEM_LINE[system], label=f"ours {system.upper()} {build}", **st[name])
            pred = series_points(table, system, build, predicted_measure, scale, ("#over", "#slow"))
            if pred:
                predicted = True
                xs, ys = zip(*pred)
                pred_ax.plot(xs, ys, linestyle="none", markerfacecolor="none", markersize=8, markeredgewidth=1.5,
                             label=f"{system.upper()} {build}, predicted (not run)", **st[name])
    return predicted, st


def overlay_thesis(ax, thesis, measure, st):
    pts = thesis_points(thesis, measure)
    for stage in ("before", "after"):
        if pts.get(stage):
            xs, ys = zip(*sorted(pts[stage]))
            ax.plot(xs, ys, ":", markersize=8, label=f"thesis TF {stage} (AMD64 3000+, 1 GB)",
                    **st[f"thesis tf {stage}"])


def log_axes(ax, ylabel):
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_ylabel(ylabel)
    ax.grid(True, which="both", alpha=0.3)


def save(fig, path):
    fig.savefig(path, dpi=130)
    plt.close(fig)
    print(f"[plots] wrote {path}", file=sys.stderr)


def table_figure(table, thesis, measures, scale, title, ylabel, path):
    """measures: (ours, the thesis', the prediction's). Measured cells and the thesis' points in the main panel,
    whose axes they alone set; the predictions of the cells not run in a panel above, with its own y axis."""
    measure, thesis_measure, predicted_measure = measures
    fig, (pred_ax, ax) = plt.subplots(2, 1, figsize=(8, 8), sharex=True, gridspec_kw={"height_ratios": [1, 2.4]})
    predicted, st = plot_builds(ax, pred_ax, table, measure, scale, predicted_measure)
    overlay_thesis(ax, thesis, thesis_measure, st)
    log_axes(ax, ylabel)
    ax.set_xlabel("vertices")
    ax.legend(fontsize=7, loc="upper left")
    ax.set_title("measured: our cells that ran, and the thesis' numbers", fontsize=9)
    if predicted:
        log_axes(pred_ax, f"predicted {ylabel}")
        pred_ax.legend(fontsize=6.5, loc="upper left", ncol=2)
        pred_ax.set_title("not run (over the memory or time budget): predicted values, hollow, own y axis",
                          fontsize=9)
    else:
        pred_ax.set_axis_off()
        pred_ax.text(0.5, 0.5, "every cell ran: no predicted-only values", ha="center", va="center",
                     transform=pred_ax.transAxes, fontsize=9)
    fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    save(fig, path)


def plot_table(results, out):
    table = cells(read_rows(os.path.join(results, "table_2_1.csv")))
    thesis = read_rows(os.path.join(results, "table_2_1_thesis.csv"))
    if not table:
        print("[plots] no table_2_1.csv: skipping the Table 2-1 plots", file=sys.stderr)
        return
    table_figure(table, thesis, ("peak_rss_bytes", "memory_mb", "predicted_bytes"), MIB,
                 "Table 2-1: memory (peak RSS of the cell; the thesis' MB are MiB: its section 2.3 divides bytes by "
                 "2^20)", "MiB", os.path.join(out, "table_2_1_memory.png"))
    table_figure(table, thesis, ("init_s", "init_s", "predicted_s"), 1.0,
                 "Table 2-1: init = build + analyze + factorize", "seconds", os.path.join(out, "table_2_1_init.png"))


def draw_fit(ax, f, scale, system, style):
    """The fitted power law over its #V range, labelled with its exponent, r^2 and n; none on fewer than
    MIN_FIT_POINTS points."""
    if not f or f["exponent"] in ("", "nan") or int(f["points"]) < MIN_FIT_POINTS:
        return
    k, c = float(f["exponent"]), float(f["coefficient"])
    lo, hi = float(f["vertices_min"]), float(f["vertices_max"])
    xs = [lo * (hi / lo) ** (i / 40) for i in range(41)]
    ax.plot(xs, [c * x ** k / scale for x in xs], "-", color=style["color"],  # a line, no marker: not data
            label=f"{system.upper()} fit: #V^{k:.2f} (r2 {float(f['r2']):.3f}, n {f['points']})")


def spread(cell, measure, scale):
    """(median, min, max) of a timed measure NAME_s over its repetitions (NAME_min_s, NAME_max_s), scaled; the value
    three times for a measure without spread (bytes)."""
    v = cell[measure]
    stem = measure[:-2] if measure.endswith("_s") else None
    lo, hi = (cell.get(f"{stem}_min_s", v), cell.get(f"{stem}_max_s", v)) if stem else (v, v)
    return v / scale, lo / scale, hi / scale


def plot_scaling(results, out):
    rows = read_rows(os.path.join(results, "scaling.csv"))
    fits = read_rows(os.path.join(results, "scaling_fits.csv"))
    if not rows:
        print("[plots] no scaling.csv: skipping scaling.png", file=sys.stderr)
        return
    data = cells(rows, ("series",))
    fit = {(f["series"], f["system"], f["measure"]): f for f in fits}
    panels = (("init_s", 1.0, "init s"), ("factor_bytes", MIB, "factor MiB"), ("frame_s", 1.0, "frame s"))
    # The tiers first: a subdivision series starts from a tier's mesh, whose cell it shares (the same size and
    # value); each cell is drawn once, in the first series that has it, so that no point reads as two agreeing
    # measurements.
    series = sorted({k[3] for k in data}, key=lambda x: (x != "tiers", x))
    st = styles(None, [f"{system} {x}" for system in ("lap", "tf") for x in series + ["fit"]])
    fig, axes = plt.subplots(1, 3, figsize=(15, 7))
    for ax, (measure, scale, label) in zip(axes, panels):
        for system in ("lap", "tf"):
            drawn = set()
            for s in series:
                # Out-of-core cells (factor on disk) drawn hollow: their frames read the factor back from the
                # page cache, and the fits leave their frame time and peak RSS out.
                for storage in ("memory", "disk"):
                    pts = sorted((c["vertices"], *spread(c, measure, scale)) for k, c in data.items()
                                 if k[1] == system and k[3] == s and c["status"] == "ok" and measure in c
                                 and c["storage"] == storage)
                    pts = [p for p in pts if (p, storage) not in drawn]  # the same cell: same size, same value
                    drawn.update((p, storage) for p in pts)
                    if pts:
                        xs, ys, lo, hi = zip(*pts)
                        face = {} if storage == "memory" else {"markerfacecolor": "none"}
                        spread_bars(ax, xs, ys, lo, hi, linestyle="none", alpha=0.75, **face, **st[f"{system} {s}"],
                                    label=f"{system.upper()} {s}" + (" (factor on disk)" if storage == "disk" else ""))
            draw_fit(ax, fit.get(("all", system, measure)), scale, system, st[f"{system} fit"])
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("vertices")
        ax.set_ylabel(label)
        ax.set_title(f"structured build: {label}" + (" (median; bar: min to max)" if measure.endswith("_s") else ""))
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=6.5, loc="upper left", bbox_to_anchor=(0.0, -0.14))  # below the axes: covers no point
    fig.tight_layout()
    path = os.path.join(out, "scaling.png")
    fig.savefig(path, dpi=130)
    plt.close(fig)
    print(f"[plots] wrote {path}", file=sys.stderr)


def plot(results, out):
    os.makedirs(out, exist_ok=True)
    plot_table(results, out)
    plot_scaling(results, out)
    return 0
