"""Predicted against measured (results/predictions.csv, written by exp_predictions): peak RSS and init time of every
Table 2-1 and solver-study cell, predicted before the cell ran (methods/run_prediction.h, the machine's calibration
from `deformbench advise --calibrate`) and measured in its fresh child. Writes results/predictions.md: per cell the
two ratios predicted / measured and whether they fall in the bands (peak RSS within +-25%, init within +-50%), and
the count that did. Reports never measure: every figure here is a column of the CSV.

    PYTHONPATH=python /usr/bin/python3 -m dbtools.report --only predictions
"""
import os

from .common import cite_figure, fmt, isnan, number, provenance, read_rows, write_atomically

PEAK_BAND, INIT_BAND = 0.25, 0.50


def ratio(row, predicted, measured):
    p, m = number(row.get(predicted)), number(row.get(measured))
    return p / m if m > 0 and not isnan(p) and not isnan(m) else float("nan")


def within(r, band):
    return not isnan(r) and 1 - band <= r <= 1 + band


def cells(rows):
    """The measured cells (status ok), each with its two ratios."""
    out = []
    for r in rows:
        if r.get("status") != "ok":
            continue
        out.append(dict(r, peak_ratio=ratio(r, "predicted_peak_bytes", "peak_rss_bytes"),
                        init_ratio=ratio(r, "predicted_init_s", "init_s")))
    return out


def label(r):
    b = r["backend"] + ("" if r["ordering"] == "default" else "/" + r["ordering"])
    return f"{r['study']} | {r['mesh']} | {r['method']} {r['build']} | {b}"


def spread(r):
    """A cell measured several times (exp_predictions --repeats): its init's range and count; its row is the median's."""
    n = number(r.get("repeats"))
    if isnan(n) or n < 2:
        return "1"
    return f"{int(n)}: {fmt(number(r['init_s_min']))}-{fmt(number(r['init_s_max']))}"


def table(ok):
    lines = ["| study | mesh | system | backend | peak RSS MB measured / predicted | ratio | init s measured / "
             "predicted | ratio | init measurements: range | in both bands |",
             "|---|---|---|---|---|---:|---|---:|---|---|"]
    for r in ok:
        pk, it = within(r["peak_ratio"], PEAK_BAND), within(r["init_ratio"], INIT_BAND)
        b = r["backend"] + ("" if r["ordering"] == "default" else "/" + r["ordering"])
        lines.append(f"| {r['study']} | {r['mesh']} | {r['method']} {r['build']} | {b} | "
                     f"{fmt(number(r['peak_rss_bytes']) / 1e6, '{:.1f}')} / "
                     f"{fmt(number(r['predicted_peak_bytes']) / 1e6, '{:.1f}')} | {fmt(r['peak_ratio'], '{:.2f}')} | "
                     f"{fmt(number(r['init_s']))} / {fmt(number(r['predicted_init_s']))} | "
                     f"{fmt(r['init_ratio'], '{:.2f}')} | {spread(r)} | {'yes' if pk and it else 'peak' if pk else 'init' if it else 'no'} |")
    return "\n".join(lines)


def write(results):
    rows = read_rows(os.path.join(results, "predictions.csv"))
    if not rows:
        return False
    ok = cells(rows)
    skipped = [r for r in rows if r.get("status") != "ok"]
    n_peak = sum(within(r["peak_ratio"], PEAK_BAND) for r in ok)
    n_init = sum(within(r["init_ratio"], INIT_BAND) for r in ok)
    miss = [label(r) for r in ok if not (within(r["peak_ratio"], PEAK_BAND) and within(r["init_ratio"], INIT_BAND))]
    prov = provenance(rows)
    text = [
        "# Predictions against measurements",
        "",
        f"{len(ok)} cells measured ({len(skipped)} not run or failed: their status below). Peak RSS within "
        f"+-{PEAK_BAND:.0%}: **{n_peak} of {len(ok)}**; init within +-{INIT_BAND:.0%}: **{n_init} of {len(ok)}**. "
        "A cell measured several times (the short ones) is compared by its median init.",
        "",
        f"Figure: {cite_figure(results, 'predictions.png', 'dbtools.plots.predictions')} (log-log, the bands shaded).",
        "",
        "Outside a band: " + ("none." if not miss else "; ".join(miss) + "."),
        "",
        table(ok),
        "",
        "Not measured: " + ("none." if not skipped else "; ".join(f"{label(r)}: {r['status']}" for r in skipped) + "."),
        "",
        f"Calibration: {rows[0].get('calibration', '') or 'none (times not predicted)'}.",
        f"Machine: {prov.get('cpu', '')}, {prov.get('blas', '')} core {prov.get('blas_core', '')}, "
        f"{prov.get('blas_threads', '')} BLAS threads; git {prov.get('git_sha', '')}, {prov.get('timestamp', '')}.",
        "",
    ]
    write_atomically(os.path.join(results, "predictions.md"), "\n".join(text))
    return True
