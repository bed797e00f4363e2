"""Figure of exp_predictions (results/predictions.csv): predicted against measured, log-log, one panel for the peak
RSS (band +-25%) and one for the init time (band +-50%), one series per backend (styles.py: its own colour and
marker); the diagonal and the band shaded.

  predictions.png

drawn by the report step: python3 -m dbtools.report --only predictions (figures into RESULTS/figures)
"""
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from ..reports.common import number, read_rows  # noqa: E402
from ..reports.predictions import INIT_BAND, PEAK_BAND  # noqa: E402
from .styles import styles  # noqa: E402

PANELS = [("peak_rss_bytes", "predicted_peak_bytes", 1e-6, "peak RSS, MB", PEAK_BAND),
          ("init_s", "predicted_init_s", 1.0, "init (build + analyze + factorize), s", INIT_BAND)]


def panel(ax, rows, st, measured, predicted, unit, title, band):
    lo, hi = float("inf"), 0.0
    for backend in st:
        pts = [(number(r[measured]) * unit, number(r[predicted]) * unit) for r in rows if r["backend"] == backend]
        pts = [(m, p) for m, p in pts if m > 0 and p > 0]
        if not pts:
            continue
        m, p = zip(*pts)
        ax.scatter(m, p, label=backend, s=28, **st[backend])
        lo, hi = min(lo, *m, *p), max(hi, *m, *p)
    if hi == 0:
        ax.set_title(title + " (nothing predicted)")
        return
    x = np.geomspace(lo / 1.5, hi * 1.5, 50)
    ax.plot(x, x, color="0.3", lw=1)
    ax.fill_between(x, x * (1 - band), x * (1 + band), color="0.85", zorder=0)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("measured")
    ax.set_ylabel("predicted")
    ax.set_title(f"{title} (shaded: +-{band:.0%})")


def plot(results, out):
    rows = [r for r in read_rows(os.path.join(results, "predictions.csv")) if r.get("status") == "ok"]
    if not rows:
        return 0
    os.makedirs(out, exist_ok=True)
    backends = sorted({r["backend"] for r in rows})
    st = styles("backend", backends)
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.5))
    for ax, (measured, predicted, unit, title, band) in zip(axes, PANELS):
        panel(ax, rows, st, measured, predicted, unit, title, band)
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="center right", fontsize=8)
    fig.tight_layout(rect=(0, 0, 0.84, 1))
    fig.savefig(os.path.join(out, "predictions.png"), dpi=110)
    plt.close(fig)
    return 0
