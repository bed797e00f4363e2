"""results/handle_frames.md and handle_drags.md: handle-mode frames against full-mode frames (issue 16), from the
CSVs experiments/handle_frames.py writes (handle_frames.csv: paired modes in one deform cell; handle_drags.csv:
per-vertex drags of growing handle size). Medians over the rounds; measures nothing. Standard library only.
"""
import os
import statistics

from .common import read_rows, write_atomically

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
           "medians over the rounds. `bytes ratio` = the responses one handle frame streams over the factor's bytes; "
           "`pays after` = the frames after which init + precompute + frames in handle mode cost less than init + "
           "frames in full mode (precompute / (full - handle)). Measured by `experiments/handle_frames.py --drags "
           f"--repeats {max(int(r['round']) for r in rows)} --frames {rows[0]['frames']}`; the exact commands are in "
           "handle_drags.csv.\n",
           "| case | method | h | full frame ms | handle frame ms | full / handle | responses MB | factor MB | "
           "bytes ratio | precompute s | pays after (frames) | handle vs full | load | rounds |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for k in keys:
        g = lambda m: med(k, m)  # noqa: E731
        gain = g("full_frame_s") - g("handle_frame_s")
        pays = f"{g('precompute_s') / gain:.0f}" if gain > 0 else "never"
        n = len([r for r in rows if (r["case"], r["method"], int(r["handle"]), r["measure"]) == (*k, "precompute_s")])
        out.append(f"| {k[0]} | {k[1]} | {k[2]} | {g('full_frame_s') * 1e3:.2f} | {g('handle_frame_s') * 1e3:.2f} | "
                   f"{g('full_frame_s') / g('handle_frame_s'):.2f} | {g('response_bytes') / 1e6:.1f} | "
                   f"{g('factor_bytes') / 1e6:.1f} | {g('response_bytes') / g('factor_bytes'):.2f} | "
                   f"{g('precompute_s'):.2f} | {pays} | "
                   f"{max(float(r['value']) for r in rows if (r['case'], r['method'], int(r['handle']), r['measure']) == (*k, 'handle_vs_full')):.1e} | "
                   f"{g('load_average'):.1f} | {n} |")
    return "\n".join(out) + "\n"


def frames_table(rows, prov):
    def med(case, method, constraints, measure):
        v = [float(r["value"]) for r in rows if (r["case"], r["method"], r["constraints"], r["measure"]) ==
             (case, method, constraints, measure)]
        return statistics.median(v) if v else float("nan"), len(v)

    out = ["# Handle-mode frames (issue 16)\n",
           f"git {prov.get('git_sha')}, {prov.get('cpu')}, {prov.get('blas')} ({prov.get('blas_core')}), "
           f"{prov.get('build_threads')} worker threads, {prov.get('timestamp')}. Medians over the rounds (fresh "
           "processes, cases interleaved); each cell runs the drag in full mode, then in handle mode on the same "
           "factor. `pass` = the responses' bytes at the memory read rate measured right after the handle drag "
           "(the least a handle frame could take). Measured by `experiments/handle_frames.py "
           f"--repeats {max(int(r['round']) for r in rows)}`; each row's exact cell command is in handle_frames.csv.\n",
           "`precompute cpu s`: its CPU time (all threads), which a loaded machine's time-slicing does not "
           "lengthen. `handle vs full`: the largest distance between the two modes' last frames / bounding-box "
           "diagonal, the worst round, on the default backend (its full frame one solve, the thesis' measure) and on "
           "multifrontal_refined (both modes refined to the exact solution: the precompute's own error).\n",
           "| case | method | full frame ms | handle frame ms | ratio | responses MB | read GB/s | pass ms | "
           "init s | precompute s | precompute cpu s | handle vs full | refined: handle vs full | rounds |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    lri = ["\nLRI's handle frame in parts (medians, ms): the frame system from its responses; the orthonormalization; "
           "the position right-hand side (the rest of rhs); the position solve.\n",
           "| case | responses | orthonormalize | position rhs | position solve |", "|---|---|---|---|---|"]
    keys = sorted({(r["case"], r["method"], r["constraints"]) for r in rows},
                  key=lambda k: (not k[0].startswith("armadillo"), k[0], METHODS.index(k[1]), k[2]))
    def worst(case, method, cons, measure):
        v = [float(r["value"]) for r in rows if (r["case"], r["method"], r["constraints"], r["measure"]) ==
             (case, method, cons, measure)]
        return f"{max(v):.1e}" if v else "-"

    for case, method, cons in keys:
        g = lambda m: med(case, method, cons, m)[0]  # noqa: E731
        n = med(case, method, cons, "frame_s")[1]
        out.append(f"| {case} ({cons}) | {method} | {g('frame_s') * 1e3:.3f} | {g('frame_handle_s') * 1e3:.3f} | "
                   f"{g('frame_s') / g('frame_handle_s'):.0f}x | {g('response_bytes') / 1e6:.1f} | "
                   f"{g('memory_read'):.1f} | {g('response_pass_s') * 1e3:.3f} | {g('init_s'):.2f} | "
                   f"{g('precompute_s'):.3f} | {g('precompute_cpu_s'):.3f} | {worst(case, method, cons, 'handle_vs_full')} | "
                   f"{worst(case, method, cons, 'refined:handle_vs_full')} | {n} |")
        if method == "lri":
            lri.append(f"| {case} ({cons}) | {g('response_s') * 1e3:.3f} | {g('orthonormalize_s') * 1e3:.3f} | "
                       f"{(g('handle_rhs_s') - g('orthonormalize_s')) * 1e3:.3f} | {g('handle_solve_s') * 1e3:.3f} |")
    return "\n".join(out + lri) + "\n"
