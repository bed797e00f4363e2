"""Figures of the LRI frame experiment, from results/frames.csv only (written by exp_frames):

  frames_ideal.png          RMS distance to the analytic ideal per case and method / frame strategy
  frames_strategy_diff.png  largest vertex difference between frame strategies (Gram-Schmidt vs polar), log scale
  frames_quality.png        edge-length distortion, ARAP energy, LRI detail error, local normal deviation
  frames_twist.png          chained bar twists: distance to the ideal and volume change against the number of turns
Every series has its own colour and marker (styles.py); a bar carries its series' marker on its top.

drawn by the report step: python3 -m dbtools.report --only frames (figures into RESULTS/figures)
"""
import csv
import math
import os
import sys

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from .styles import styles  # noqa: E402

MAIN = [  # (config, label)
    ("lap", "LAP"),
    ("tf", "TF"),
    ("tf-normalized", "TF normalized scale"),
    ("lri-first-gram_schmidt", "LRI first / GS"),
    ("lri-random-gram_schmidt", "LRI random / GS"),
    ("lri-height_angle-gram_schmidt", "LRI height angle / GS"),
    ("lri-curvature-gram_schmidt", "LRI curvature / GS"),
    ("lri-first-polar", "LRI first / polar"),
]
STYLE = styles("config", [cfg for cfg, _ in MAIN])
STRATEGIES = ["random", "height_angle", "curvature"]


def value(row, key):
    v = row.get(key, "n/a")
    try:
        return float(v)
    except ValueError:
        return math.nan  # "n/a" (open mesh, no ideal, failed configuration)


def load(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    cases = []
    for r in rows:
        if r["case"] not in cases:
            cases.append(r["case"])
    by = {(r["case"], r["config"]): r for r in rows}
    return rows, cases, by


def grouped_bars(ax, cases, by, key, configs, log=False):
    width = 0.8 / len(configs)
    x = np.arange(len(cases))
    for k, (cfg, label) in enumerate(configs):
        st = STYLE[cfg]
        vals = np.array([value(by.get((c, cfg), {}), key) for c in cases])
        pos = x - 0.4 + width * (k + 0.5)
        ok = ~np.isnan(vals)
        ax.bar(pos[ok], vals[ok], width, color=st["color"], alpha=0.85)
        ax.plot(pos[ok], vals[ok], linestyle="none", markersize=5, markeredgecolor="black", markeredgewidth=0.4,
                label=label, **st)
        failed = [i for i, c in enumerate(cases) if by.get((c, cfg), {}).get("status", "ok") != "ok"]
        if failed:
            ax.plot(pos[failed], np.zeros(len(failed)) + (1e-3 if log else 0), "x", color=st["color"], ms=7, mew=2)
    ax.set_xticks(x)
    ax.set_xticklabels(cases, rotation=35, ha="right", fontsize=8)
    if log:
        ax.set_yscale("log")
    ax.grid(axis="y", alpha=0.3)


def fig_ideal(cases, by, out):
    with_ideal = [c for c in cases if not math.isnan(value(by.get((c, "lap"), {}), "ideal_rms"))]
    if not with_ideal:
        return None
    fig, ax = plt.subplots(figsize=(max(8, 1.3 * len(with_ideal)), 5))
    grouped_bars(ax, with_ideal, by, "ideal_rms", MAIN)
    ax.set_ylabel("RMS distance to the analytic ideal / bbox diagonal")
    ax.set_title("Distance to the ideal deformation (x: configuration failed, see status)")
    ax.legend(fontsize=8, ncol=2)
    fig.tight_layout()
    path = os.path.join(out, "frames_ideal.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


FAILED_Y = 0.3  # where fig_strategy_diff marks a failed configuration: above any difference it draws


def fig_strategy_diff(cases, by, out):
    floor = 1e-17  # identical results plot on the floor
    fig, ax = plt.subplots(figsize=(max(8, 0.8 * len(cases)), 5))
    x = np.arange(len(cases))
    orthos = (("gram_schmidt", "Gram-Schmidt"), ("polar", "polar"))
    st = styles(None, [f"{s}, {name}" for s in STRATEGIES for _, name in orthos])
    for s in STRATEGIES:
        for ortho, name in orthos:
            vals = np.array([value(by.get((c, f"lri-{s}-{ortho}"), {}), "diff_vs_first_max") for c in cases])
            vals = np.where(np.isnan(vals), np.nan, np.maximum(vals, floor))
            off = {"random": -0.2, "height_angle": 0.0, "curvature": 0.2}[s] + (0.05 if ortho == "polar" else -0.05)
            ax.plot(x + off, vals, linestyle="none", markersize=6, label=f"{s}, {name}", **st[f"{s}, {name}"])
            failed = [i for i, c in enumerate(cases) if math.isnan(vals[i]) and (c, f"lri-{s}-{ortho}") in by]
            if failed:  # no difference to draw: the configuration (or the first-neighbour one) failed
                ax.plot(x[failed] + off, np.full(len(failed), FAILED_Y), "x", color=st[f"{s}, {name}"]["color"], ms=7,
                        mew=2)
    sig = np.array([value(by.get((c, "lri-first-polar"), {}), "frame_sigma_min") for c in cases])
    for i, sv in enumerate(sig):
        if sv < 1e-3:
            ax.axvspan(i - 0.45, i + 0.45, color="0.85", zorder=0)
    ax.set_yscale("log")
    ax.set_ylim(floor / 3, 1)
    ax.set_xticks(x)
    ax.set_xticklabels(cases, rotation=35, ha="right", fontsize=8)
    ax.set_ylabel("max |x - x_first| / bbox diagonal")
    ax.set_title("Frame strategy against first-neighbour frames (grey: a solved frame collapsed; x at the top: "
                 "failed, no difference)", fontsize=9)
    ax.grid(axis="y", alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.005, 1.0))
    fig.tight_layout()
    path = os.path.join(out, "frames_strategy_diff.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


# The configurations frames.md tabulates for rigidity and detail (reports/frames.py ideal_tables), plus TF with its
# scale normalized: the LRI default (first neighbour, Gram-Schmidt), the best GS strategy and polar frames.
QUALITY = ("lap", "tf", "tf-normalized", "lri-first-gram_schmidt", "lri-height_angle-gram_schmidt", "lri-first-polar")


def fig_quality(cases, by, out):
    configs = [(cfg, label) for cfg, label in MAIN if cfg in QUALITY]
    panels = [("edge_distortion", "relative RMS edge-length distortion", True),
              ("arap_energy", "ARAP energy (relative)", True),
              ("lri_detail_error", "LRI detail error (relative)", True),
              ("normal_dev_local_mean_deg", "local normal deviation, mean (deg)", True)]
    fig, axes = plt.subplots(2, 2, figsize=(max(12, 1.4 * len(cases)), 9))
    for ax, (key, title, log) in zip(axes.flat, panels):
        grouped_bars(ax, cases, by, key, configs, log=log)
        ax.set_title(title, fontsize=10)
    handles, labels = axes.flat[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="upper center", ncol=len(configs), fontsize=9)
    fig.text(0.5, 0.005, "x: the configuration failed on that case (no value; see its status in frames.csv)",
             ha="center", fontsize=9)
    fig.tight_layout(rect=(0, 0.02, 1, 0.96))
    path = os.path.join(out, "frames_quality.png")
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path


def fig_twist(rows, out):
    tw = [r for r in rows if r["family"] == "bar_twist" and r["protocol"] == "chained"]
    if not tw:
        return None
    fig, axes = plt.subplots(1, 2, figsize=(14, 4.5))
    for cfg, label in MAIN:
        pts = sorted((value(r, "angle_deg") / 360, value(r, "ideal_rms"), value(r, "volume_change"))
                     for r in tw if r["config"] == cfg)
        if not pts:
            continue
        t, d, v = map(np.array, zip(*pts))
        axes[0].plot(t, d, "-", label=label, **STYLE[cfg])
        axes[1].plot(t, v, "-", label=label, **STYLE[cfg])
    axes[0].set_ylabel("RMS distance to ideal_twist / bbox diagonal")
    axes[1].set_ylabel("relative volume change")
    for ax in axes:
        ax.set_xlabel("full turns (chained edits)")
        ax.grid(alpha=0.3)
    axes[1].legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1.0))  # outside: covers no point
    steps = sorted({int(r["steps"]) for r in tw})
    fig.suptitle(f"Bar twists as chains of edits ({', '.join(map(str, steps))} steps)")
    fig.tight_layout()
    path = os.path.join(out, "frames_twist.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def plot(results, out):
    path = os.path.join(results, "frames.csv")
    if not os.path.exists(path):
        print(f"frames: {path} missing (run exp_frames first); nothing to plot", file=sys.stderr)
        return 0
    rows, cases, by = load(path)
    os.makedirs(out, exist_ok=True)
    for p in (fig_ideal(cases, by, out), fig_strategy_diff(cases, by, out), fig_quality(cases, by, out),
              fig_twist(rows, out)):
        if p:
            print(f"frames: wrote {p}", file=sys.stderr)
    return 0
