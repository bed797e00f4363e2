#!/usr/bin/env python3
"""Plots of thesis Table 2-1 (experiments/table_2_1.cpp). Reads CSVs only, never recomputes a measurement.

  table_2_1.py --results DIR --out DIR

Reads RESULTS/table_2_1.csv, table_2_1_thesis.csv, scaling.csv and scaling_fits.csv and writes
  OUT/table_2_1_memory.png  peak RSS per cell against #V, log-log; dense cells over budget at their predicted bytes
                            (hollow); the thesis' TF memory before / after overlaid
  OUT/table_2_1_init.png    init time (build + analyze + factorize) against #V, thesis points overlaid
  OUT/scaling.png           structured build: init, factor bytes and frame time against #V with the fitted
                            power laws (exponents from scaling_fits.csv)
Run with Debian's /usr/bin/python3 (numpy + matplotlib).
"""
import argparse
import csv
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

MIB = 1024.0 * 1024.0
BUILD_STYLE = {"dense": ("tab:red", "s"), "naive": ("tab:orange", "^"), "structured": ("tab:blue", "o")}
SYSTEM_LINE = {"tf": "-", "lap": "--"}


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


def plot_builds(ax, table, measure, scale, predicted_measure=None):
    for system in ("tf", "lap"):
        for build, (color, marker) in BUILD_STYLE.items():
            ok = sorted((c["vertices"], c[measure] / scale) for k, c in table.items()
                        if k[1] == system and k[2] == build and c["status"] == "ok" and measure in c
                        and "vertices" in c)
            if ok:
                xs, ys = zip(*ok)
                ax.plot(xs, ys, SYSTEM_LINE[system], color=color, marker=marker,
                        label=f"ours {system.upper()} {build}")
            if predicted_measure:
                pred = sorted((c["vertices"], c[predicted_measure] / scale) for k, c in table.items()
                              if k[1] == system and k[2] == build and c["status"] in ("#over", "#slow")
                              and predicted_measure in c and "vertices" in c)
                if pred:
                    xs, ys = zip(*pred)
                    ax.plot(xs, ys, linestyle="none", marker=marker, markerfacecolor="none", color=color,
                            label=f"ours {system.upper()} {build}, predicted (not run)")


def overlay_thesis(ax, thesis, measure):
    pts = thesis_points(thesis, measure)
    for stage, marker in (("before", "x"), ("after", "+")):
        if pts.get(stage):
            xs, ys = zip(*sorted(pts[stage]))
            ax.plot(xs, ys, ":", color="black", marker=marker, markersize=9,
                    label=f"thesis TF {stage} (AMD64 3000+, 1 GB)")


def finish(ax, fig, title, ylabel, path):
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("vertices")
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    print(f"[plots] wrote {path}", file=sys.stderr)


def plot_table(results, out):
    table = cells(read_rows(os.path.join(results, "table_2_1.csv")))
    thesis = read_rows(os.path.join(results, "table_2_1_thesis.csv"))
    if not table:
        print("[plots] no table_2_1.csv: skipping the Table 2-1 plots", file=sys.stderr)
        return
    fig, ax = plt.subplots(figsize=(7.5, 5.5))
    plot_builds(ax, table, "peak_rss_bytes", MIB, "predicted_bytes")
    overlay_thesis(ax, thesis, "memory_mb")
    finish(ax, fig, "Table 2-1: memory (peak RSS of the cell; thesis MB)", "MiB",
           os.path.join(out, "table_2_1_memory.png"))
    fig, ax = plt.subplots(figsize=(7.5, 5.5))
    plot_builds(ax, table, "init_s", 1.0, "predicted_s")
    overlay_thesis(ax, thesis, "init_s")
    finish(ax, fig, "Table 2-1: init = build + analyze + factorize", "seconds",
           os.path.join(out, "table_2_1_init.png"))


def plot_scaling(results, out):
    rows = read_rows(os.path.join(results, "scaling.csv"))
    fits = read_rows(os.path.join(results, "scaling_fits.csv"))
    if not rows:
        print("[plots] no scaling.csv: skipping scaling.png", file=sys.stderr)
        return
    data = cells(rows, ("series",))
    fit = {(f["series"], f["system"], f["measure"]): f for f in fits}
    panels = (("init_s", 1.0, "init s"), ("factor_bytes", MIB, "factor MiB"), ("frame_s", 1.0, "frame s"))
    series = sorted({k[3] for k in data})
    markers = dict(zip(series, "osD^v<>"))
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.8))
    for ax, (measure, scale, label) in zip(axes, panels):
        for system, color in (("lap", "tab:green"), ("tf", "tab:purple")):
            for s in series:
                # Out-of-core cells (factor on disk) drawn hollow: their frames read the factor back from the
                # page cache, and the fits leave their frame time and peak RSS out.
                for storage, face in (("memory", color), ("disk", "none")):
                    pts = sorted((c["vertices"], c[measure] / scale) for k, c in data.items()
                                 if k[1] == system and k[3] == s and c["status"] == "ok" and measure in c
                                 and c["storage"] == storage)
                    if pts:
                        xs, ys = zip(*pts)
                        ax.plot(xs, ys, linestyle="none", marker=markers[s], color=color, markerfacecolor=face,
                                alpha=0.75,
                                label=f"{system.upper()} {s}" + (" (factor on disk)" if storage == "disk" else ""))
            f = fit.get(("all", system, measure))
            if f and f["exponent"] not in ("", "nan"):
                k, c = float(f["exponent"]), float(f["coefficient"])
                lo, hi = float(f["vertices_min"]), float(f["vertices_max"])
                xs = [lo * (hi / lo) ** (i / 40) for i in range(41)]
                ax.plot(xs, [c * x ** k / scale for x in xs], "-", color=color,
                        label=f"{system.upper()} fit: #V^{k:.2f} (r2 {float(f['r2']):.3f})")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("vertices")
        ax.set_ylabel(label)
        ax.set_title(f"structured build: {label}")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=6.5, loc="upper left")
    fig.tight_layout()
    path = os.path.join(out, "scaling.png")
    fig.savefig(path, dpi=130)
    plt.close(fig)
    print(f"[plots] wrote {path}", file=sys.stderr)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--results", default="results")
    p.add_argument("--out", default="plots")
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    plot_table(a.results, a.out)
    plot_scaling(a.results, a.out)


if __name__ == "__main__":
    main()
