"""results/handle_frames.md and handle_drags.md: handle-mode frames against full-mode frames (issue 16), from the
CSVs experiments/handle_frames.py writes (handle_frames.csv: paired modes in one deform cell; handle_drags.csv:
per-vertex drags of growing handle size). Medians over the rounds; measures nothing. Standard library only.
"""
import math
import os
import statistics

from .common import FLAG, NAN, SPREAD_NOTE, read_rows, repeated_spread, spread_name, write_atomically

METHODS = ["lap", "tf", "lri"]  # the driver's methods, in the order the table lists them


def write_frames(results):
    """Writes RESULTS/handle_frames.md; False when there is no handle_frames.csv."""
    rows = read_rows(os.path.join(results, "handle_frames.csv"))
    if rows:
        write_atomically(os.path.join(results, "handle_frames.md"), frames_table(rows, rows[0]))
    return bool(rows)


def write_drags(results):
    """Writes RESULTS/handle_drags.md; False when there is no handle_drags.csv."""
    rows = read_rows(os.path.join(results, "handle_drags.csv"))
    if rows:
        write_atomically(os.path.join(results, "handle_drags.md"), drags_table(rows, rows[0]))
    return bool(rows)


def drags_table(rows, prov):
    keys = sorted({(r["case"], r["method"], int(r["handle"])) for r in rows},
                  key=lambda k: (k[0] != "armadillo_26k", k[1], k[2]))
    med = lambda k, m: statistics.median(float(r["value"]) for r in rows  # noqa: E731
                                         if (r["case"], r["method"], int(r["handle"]), r["measure"]) == (*k, m))
    out = ["# Per-vertex drags: handle-mode frames against full frames (issue 16, item 3)\n",
           f"git {prov.get('git_sha')}, {prov.get('cpu')}, {prov.get('blas')} ({prov.get('blas_core')}), "
           f"{prov.get('build_threads')} worker threads, {prov.get('timestamp')}. Each case: the h vertices nearest the "
           "armadillo's head lifted by 5% of the diagonal and bent across the handle (a smooth, non-affine drag), the feet "
           "(lowest 5% of the height) fixed, soft constraints (every vertex an unknown), `deformbench deform` "
           "in full mode and in handle mode (`--handle-limit 1e6`), paired back to back, rounds interleaving the cases; "
           "medians over the rounds, the frame and precompute times with their spread over the rounds (least - "
           "largest, n) where there are several. `bytes ratio` = the responses one handle frame streams over the factor's bytes; "
           "`pays after` = the frames after which init + precompute + frames in handle mode cost less than init + "
           "frames in full mode (precompute / (full - handle)). Measured by `experiments/handle_frames.py --drags "
           f"--repeats {max(int(r['round']) for r in rows)} --frames {rows[0]['frames']}`; the exact commands are in "
           "handle_drags.csv.\n",
           "| case | method | h | full frame ms | handle frame ms | full / handle | responses MB | factor MB | "
           "bytes ratio | precompute s | pays after (frames) | handle vs full | load | rounds |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    cells = by_round(rows, ("case", "method", "handle"))
    for k in keys:
        g = lambda m: med(k, m)  # noqa: E731
        vals = cells[(k[0], k[1], str(k[2]))]
        gain = g("full_frame_s") - g("handle_frame_s")
        pays = f"{g('precompute_s') / gain:.0f}" if gain > 0 else "never"
        n = len([r for r in rows if (r["case"], r["method"], int(r["handle"]), r["measure"]) == (*k, "precompute_s")])
        out.append(f"| {k[0]} | {k[1]} | {k[2]} | {timed(vals, 'full_frame_s', 1e3, '{:.2f}')} | "
                   f"{timed(vals, 'handle_frame_s', 1e3, '{:.2f}')} | "
                   f"{g('full_frame_s') / g('handle_frame_s'):.2f} | {g('response_bytes') / 1e6:.1f} | "
                   f"{g('factor_bytes') / 1e6:.1f} | {g('response_bytes') / g('factor_bytes'):.2f} | "
                   f"{timed(vals, 'precompute_s', 1, '{:.2f}')} | {pays} | "
                   f"{max(float(r['value']) for r in rows if (r['case'], r['method'], int(r['handle']), r['measure']) == (*k, 'handle_vs_full')):.1e} | "
                   f"{g('load_average'):.1f} | {n} |")
    return "\n".join(out) + "\n"


def by_round(rows, key_columns):
    """{key: {measure: {round: value}}} of a long CSV, the key a tuple of `key_columns`."""
    out = {}
    for r in rows:
        key = tuple(r[c] for c in key_columns)
        out.setdefault(key, {}).setdefault(r["measure"], {})[r["round"]] = float(r["value"])
    return out


def timed(vals, m, scale=1e3, spec="{:.3f}"):
    """A timing's median over the rounds with its spread (least - largest, n): over every repeat of every round where
    the rounds record their own spread (NAME_min_s, NAME_max_s, NAME_reps), else over the rounds' values."""
    v = list(vals.get(m, {}).values())
    if not v:
        return "-"
    lo_hi = [list(vals.get(spread_name(m, k), {}).values()) for k in ("min", "max", "reps")]
    if lo_hi[0] and lo_hi[1]:
        lo, hi, n = min(lo_hi[0]), max(lo_hi[1]), sum(lo_hi[2]) or len(v)
    else:
        lo, hi, n = min(v), max(v), len(v)
    d = {m: statistics.median(v), spread_name(m, "min"): lo, spread_name(m, "max"): hi, spread_name(m, "reps"): n}
    form = lambda x: spec.format(x * scale)  # noqa: E731
    return form(d[m]) + repeated_spread(lambda k: d.get(k, NAN), m, form)


def ranged(v, form, unit=""):
    """A median over the rounds, with the rounds' range where there are several and they differ."""
    if not v:
        return "-"
    text = form(statistics.median(v)) + unit
    return text + (f" ({form(min(v))} - {form(max(v))})" if len(v) > 1 and form(min(v)) != form(max(v)) else "")


def sig2(x):
    """Two significant digits without an exponent: 1.4, 48, 280, 0.43."""
    return f"{float(f'{x:.2g}'):g}" if math.isfinite(x) else "-"


def ratio(vals):
    """full / handle frame time per round (the two modes are paired in one process): median and range."""
    full, hand = vals.get("frame_s", {}), vals.get("frame_handle_s", {})
    rs = [full[k] / hand[k] for k in full if k in hand and hand[k] > 0]
    return ranged(rs, sig2, "x")


def worst(vals, measure):
    v = list(vals.get(measure, {}).values())
    return f"{max(v):.1e}" if v else "-"


def frames_row(case, method, cons, vals):
    med = lambda m, scale=1.0, spec="{:.1f}": ranged(  # noqa: E731
        list(vals.get(m, {}).values()), lambda x: spec.format(x * scale))
    return (f"| {case} ({cons}) | {method} | {timed(vals, 'frame_s')} | {timed(vals, 'frame_handle_s')} | "
            f"{ratio(vals)} | {med('response_bytes', 1e-6)} | {med('memory_read')} | {timed(vals, 'response_pass_s')} | "
            f"{timed(vals, 'init_s', 1, '{:.2f}')} | {timed(vals, 'precompute_s', 1)} | "
            f"{timed(vals, 'precompute_cpu_s', 1)} | {worst(vals, 'handle_vs_full')} | "
            f"{worst(vals, 'refined:handle_vs_full')} | {len(vals.get('frame_s', {}))} |")


def lri_row(case, cons, vals):
    """LRI's handle frame in parts; the position right-hand side is handle_rhs_s less the orthonormalization, per
    round."""
    rhs, ortho = vals.get("handle_rhs_s", {}), vals.get("orthonormalize_s", {})
    rest = {"position_rhs_s": {k: rhs[k] - ortho[k] for k in rhs if k in ortho}}
    return (f"| {case} ({cons}) | {timed(vals, 'response_s')} | {timed(vals, 'orthonormalize_s')} | "
            f"{timed(rest, 'position_rhs_s')} | {timed(vals, 'handle_solve_s')} |")


def frames_table(rows, prov):
    out = ["# Handle-mode frames (issue 16)\n",
           f"git {prov.get('git_sha')}, {prov.get('cpu')}, {prov.get('blas')} ({prov.get('blas_core')}), "
           f"{prov.get('build_threads')} worker threads, {prov.get('timestamp')}. Medians over the rounds (fresh "
           "processes, cases interleaved), each time with its spread (least - largest, n): over every frame of every "
           "round where the cells record their frames' spread, else over the rounds; `read GB/s` and `responses MB` "
           "with the rounds' range. Each cell runs the drag in full mode, then in handle mode on the same "
           "factor. `ratio`: full frame over handle frame per round (the two modes are paired in one process), its "
           "median and range over the rounds, two significant digits. `pass` = the responses' bytes at the memory "
           "read rate measured right after the handle drag "
           "(the least a handle frame could take). Measured by `experiments/handle_frames.py "
           f"--repeats {max(int(r['round']) for r in rows)}`; each row's exact cell command is in handle_frames.csv.\n",
           "`precompute cpu s`: its CPU time (all threads), which a loaded machine's time-slicing does not "
           "lengthen. `handle vs full`: the largest distance between the two modes' last frames / bounding-box "
           "diagonal, the worst round, on the default backend (its full frame one solve, the thesis' measure) and on "
           "multifrontal_refined (both modes refined to the exact solution: the precompute's own error).\n",
           "| case | method | full frame ms | handle frame ms | ratio | responses MB | read GB/s | pass ms | "
           "init s | precompute s | precompute cpu s | handle vs full | refined: handle vs full | rounds |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    lri = ["\nLRI's handle frame in parts (medians with their spread, ms): the frame system from its responses; the "
           "orthonormalization; the position right-hand side (the rest of rhs); the position solve.\n",
           "| case | responses | orthonormalize | position rhs | position solve |", "|---|---|---|---|---|"]
    cells = by_round(rows, ("case", "method", "constraints"))
    keys = sorted(cells, key=lambda k: (not k[0].startswith("armadillo"), k[0], METHODS.index(k[1]), k[2]))
    for case, method, cons in keys:
        out.append(frames_row(case, method, cons, cells[(case, method, cons)]))
        if method == "lri":
            lri.append(lri_row(case, cons, cells[(case, method, cons)]))
    flagged = sum(line.count(FLAG) for line in out + lri)
    return "\n".join(out + lri) + f"\n\n{SPREAD_NOTE} Flagged here: {flagged}.\n"
