"""Plots of the solver-choice experiment (experiments/solvers.cpp). Reads CSVs only, never recomputes.

  drawn by the report step: python3 -m dbtools.report --only solvers (figures into RESULTS/figures)

Reads RESULTS/solvers.csv (and RESULTS/solvers_blas_*.csv when present) and writes
  OUT/solvers_factorize_vs_solve.png  factorize against per-solve time, per backend (default ordering)
  OUT/solvers_scaling.png             factorize and solve time against the number of unknowns n (the fastest
                                      repetition, a bar up to the slowest)
  OUT/solvers_orderings.png           nnz(L) and factorize time per ordering, sparse direct backends, largest tier
  OUT/solvers_blas.png                factorize time per OpenBLAS kernel set: only when the runs report more than
                                      one distinct core (dbtools/reports/kernel_sets.py); else it is removed
Every series has its own colour and marker (styles.py).
"""
import csv
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from ..reports.kernel_sets import kernel_sets  # noqa: E402
from .bars import spread_bars  # noqa: E402
from .styles import styles  # noqa: E402

SYSTEMS = ["lap", "tf"]  # a panel per system that has cells (systems_in)
# Minimum over a cell's repetitions (interference from other jobs only adds time), as in results/solvers.md.
FACT = "factorize_min_s"
SOLVE = "solve_min_s"
FAMILY_STYLE = {"sparse-cholesky": "-", "sparse-lu": "--", "dense": ":", "iterative": "-."}


def load(path):
    """(model, system, backend, ordering) -> {measure: value} for ok cells, plus per-cell metadata; a run at several
    thread counts (--threads) at its smallest, as results/solvers.md reads it."""
    cells = defaultdict(dict)
    meta = {}
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    counts = sorted({int(r["threads"]) for r in rows if r.get("threads")})
    for row in rows:
        if counts and row.get("threads") and int(row["threads"]) != counts[0]:
            continue
        key = (row["model"], row["system"], row["backend"], row["ordering"])
        meta[key] = row
        if row["status"] != "ok" or row["value"] == "":
            continue
        cells[key][row["measure"]] = float(row["value"])
    return cells, meta


def systems_in(cells):
    return [s for s in SYSTEMS if any(k[1] == s for k in cells)]


def backends_in(cells):
    seen = []
    for (_, _, b, _) in cells:
        if b not in seen:
            seen.append(b)
    return seen


def style(meta, backend):
    fam = next((m["family"] for k, m in meta.items() if k[2] == backend), "")
    return FAMILY_STYLE.get(fam, "-")


def plot_factor_vs_solve(cells, meta, out):
    bks = backends_in(cells)
    st = styles("backend", bks)
    systems = systems_in(cells)
    fig, axes = plt.subplots(1, len(systems), figsize=(6.5 * len(systems) + 2, 5.5), squeeze=False)
    axes = axes[0]
    for ax, system in zip(axes, systems):
        for b in bks:
            pts = sorted((v["n"], v[FACT], v[SOLVE], k[0]) for k, v in cells.items()
                         if k[1] == system and k[2] == b and k[3] == "default"
                         and FACT in v and SOLVE in v)
            if not pts:
                continue
            xs = [max(p[1], 1e-7) for p in pts]
            ys = [max(p[2], 1e-7) for p in pts]
            ax.plot(xs, ys, style(meta, b), label=b, **st[b])
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("factorize time [s] (once per edit)")
        ax.set_ylabel("solve time [s] (every frame)")
        # The models in the order each backend's line passes them (a label per point would overlap 17 backends').
        models = [m for _, m in sorted({(v["n"], k[0]) for k, v in cells.items() if k[1] == system and "n" in v})]
        ax.set_title(f"{system}: factorize vs solve, default ordering\neach line's points, by unknowns: "
                     + ", ".join(models), fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
    axes[-1].legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0))  # outside: covers no point
    fig.tight_layout()
    fig.savefig(os.path.join(out, "solvers_factorize_vs_solve.png"), dpi=120)
    plt.close(fig)


def plot_scaling(cells, meta, out):
    bks = backends_in(cells)
    st = styles("backend", bks)
    systems = systems_in(cells)
    fig, axes = plt.subplots(2, len(systems), figsize=(6.5 * len(systems) + 2, 9), sharex="col", squeeze=False)
    for j, system in enumerate(systems):
        for i, (measure, label) in enumerate([(FACT, "factorize [s]"), (SOLVE, "solve [s]")]):
            ax = axes[i][j]
            top = measure.replace("_min_s", "_max_s")
            for b in bks:
                pts = sorted((v["n"], max(v[measure], 1e-7), max(v.get(top, v[measure]), 1e-7))
                             for k, v in cells.items()
                             if k[1] == system and k[2] == b and k[3] == "default" and measure in v and "n" in v)
                if not pts:
                    continue
                n, lo, hi = zip(*pts)  # the bar: from the minimum (the point) up to the largest repetition
                spread_bars(ax, n, lo, lo, hi, linestyle=style(meta, b), label=b, **st[b])
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_ylabel(label)
            ax.set_title(f"{system}: {label.split()[0]} vs unknowns\n(point: fastest repetition; bar: up to the "
                         "slowest)", fontsize=10)
            ax.grid(True, which="both", alpha=0.3)
            if i == 1:
                ax.set_xlabel("unknowns n")
    axes[0][-1].legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0))  # outside: covers no point
    fig.tight_layout()
    fig.savefig(os.path.join(out, "solvers_scaling.png"), dpi=120)
    plt.close(fig)


def same_as_default(meta, key):
    """Whether a cell ran the ordering its backend's default ran (ordering_used, e.g. metis-block3 for TF): the
    same ordering under a second name, whose difference from the default cell is timing noise."""
    model, system, backend, ordering = key
    default = meta.get((model, system, backend, "default"), {}).get("ordering_used")
    return ordering != "default" and bool(default) and meta.get(key, {}).get("ordering_used") == default


def plot_orderings(cells, meta, out):
    """A dot per (backend, ordering) on a log axis, backends side by side, one style per ordering."""
    models = []
    for k in meta:
        if k[0] not in models:
            models.append(k[0])
    if not models:
        return
    big = max(models, key=lambda m: max((v.get("vertices", 0) for k, v in cells.items() if k[0] == m), default=0))
    direct = [k for k in meta if k[0] == big and meta[k]["family"] in ("sparse-cholesky", "sparse-lu")]
    backends = []
    orderings = []
    for k in direct:
        if k[2] not in backends:
            backends.append(k[2])
        if k[3] not in orderings:
            orderings.append(k[3])
    if not backends:
        return
    st = styles("ordering", orderings)
    width = 0.8 / len(orderings)
    systems = systems_in(cells)
    fig, axes = plt.subplots(2, len(systems), figsize=(7 * len(systems), 9), squeeze=False)
    for j, system in enumerate(systems):
        for i, (measure, ylabel) in enumerate([("nnz_factor", "nnz(L) (L+U for LU)"), (FACT, "factorize [s]")]):
            ax = axes[i][j]
            for o, ordering in enumerate(orderings):
                xs, ys = [], []
                for g, b in enumerate(backends):
                    v = cells.get((big, system, b, ordering), {}).get(measure)
                    if v is not None and v > 0 and not same_as_default(meta, (big, system, b, ordering)):
                        xs.append(g + (o + 0.5) * width - 0.4)
                        ys.append(v)
                if xs:  # an ordering with no point in any panel gets no legend entry
                    ax.plot(xs, ys, linestyle="none", markersize=7, markeredgecolor="black", markeredgewidth=0.4,
                            label=ordering, **st[ordering])
            for g in range(1, len(backends)):
                ax.axvline(g - 0.5, color="0.85", linewidth=0.8, zorder=0)
            ax.set_yscale("log")
            ax.set_xlim(-0.5, len(backends) - 0.5)
            ax.set_xticks(range(len(backends)))
            ax.set_xticklabels(backends, rotation=20, fontsize=8, ha="right", rotation_mode="anchor")
            ax.set_ylabel(ylabel)
            ax.set_title(f"{big} {system}: {ylabel} per ordering", fontsize=10)
            ax.grid(True, axis="y", which="both", alpha=0.3)
    axes[0][0].legend(fontsize=7, ncol=2, title="ordering (missing: skipped / same as default)", title_fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "solvers_orderings.png"), dpi=120)
    plt.close(fig)


def plot_blas(results, out):
    """Factorize time per kernel set, one series per distinct core OpenBLAS reported; with one core there is
    nothing to compare, and a stale plot from an earlier run is removed."""
    path = os.path.join(out, "solvers_blas.png")
    distinct, duplicates = kernel_sets(results)
    for core, kset, p in duplicates:
        print(f"solvers.py: {os.path.basename(p)} (core {core}) has the {kset} kernels of an earlier run: left out",
              file=sys.stderr)
    if len(distinct) < 2:
        if os.path.exists(path):
            os.remove(path)
        print("solvers.py: one distinct BLAS kernel set: no solvers_blas.png", file=sys.stderr)
        return
    runs = [(core if kset == core else f"{core} ({kset} kernels)", load(p)[0]) for core, kset, p in distinct]
    keys = sorted(k for k in runs[1][1] if k[3] == "default" and FACT in runs[1][1][k] and k in runs[0][1])
    if not keys:
        return
    st = styles(None, [core for core, _ in runs])
    fig, ax = plt.subplots(figsize=(max(8, 0.5 * len(keys) + 3), 5.5))
    for r, (core, c) in enumerate(runs):
        ys = [c.get(k, {}).get(FACT, float("nan")) for k in keys]
        xs = [i + (r + 0.5) * 0.8 / len(runs) - 0.4 for i in range(len(keys))]
        ax.plot(xs, ys, linestyle="none", markersize=7, markeredgecolor="black", markeredgewidth=0.4,
                label=f"core {core}" + (" (this run)" if r == 0 else ""), **st[core])
    ax.set_xlim(-0.5, len(keys) - 0.5)
    ax.set_xticks(range(len(keys)))
    ax.set_xticklabels([f"{k[0]}/{k[1]}\n{k[2]}" for k in keys], rotation=90, fontsize=7)
    ax.set_yscale("log")
    ax.set_ylabel("factorize [s] (minimum over repetitions)")
    ax.set_title("factorize time per OpenBLAS kernel set (dense_llt = Eigen, no BLAS: control)")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))  # outside: covers no point
    ax.grid(True, axis="y", which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot(results, out):
    path = os.path.join(results, "solvers.csv")
    if not os.path.exists(path):
        print(f"solvers: {path} not found (run exp_solvers); nothing to plot", file=sys.stderr)
        return 0
    os.makedirs(out, exist_ok=True)
    cells, meta = load(path)
    if not systems_in(cells):
        print(f"solvers: no cell of {path} ran; nothing to plot", file=sys.stderr)
        return 0
    plot_factor_vs_solve(cells, meta, out)
    plot_scaling(cells, meta, out)
    plot_orderings(cells, meta, out)
    plot_blas(results, out)
    return 0
