"""results/table_2_1.md from the CSVs exp_table_2_1 wrote (table_2_1.csv, table_2_1_thesis.csv, scaling.csv,
scaling_fits.csv, table_2_1_settings.csv): the thesis' layout with its numbers beside ours, ratios, memory and
phase times in detail, the targets at the 104k tier and the scaling fits. Reads CSVs only, never measures."""
import os

from .common import (FLAG, MIB, NAN, SPREAD_NOTE, cells, fmt, median, isnan, mark, number, provenance, read_rows,
                    settings, spread_text, write_atomically)

# The timings the tables show, each with its spread or flag; fps and fps_handle follow their frame's.
FLAG_OF = {"fps": "frame_s", "fps_handle": "frame_handle_s"}

KEY = ("model", "system", "build", "backend", "factor_storage", "ordering_used")
SCALING_KEY = ("series", "level") + KEY


class Run:
    """What the report reads: the cells, the thesis' rows, the settings and the scaling series."""

    def __init__(self, results):
        rows = read_rows(os.path.join(results, "table_2_1.csv"))
        self.rows = rows
        self.cells = cells(rows, KEY)
        for c in self.cells:
            c.vertices = number(c.row.get("vertices"))
        self.thesis = thesis_rows(read_rows(os.path.join(results, "table_2_1_thesis.csv")))
        self.settings = settings(os.path.join(results, "table_2_1_settings.csv"))
        self.scaling = cells(read_rows(os.path.join(results, "scaling.csv")), SCALING_KEY)
        for c in self.scaling:
            c.vertices = number(c.row.get("vertices"))
        self.fits = read_rows(os.path.join(results, "scaling_fits.csv"))
        self.models = []
        for c in self.cells:
            if c.model not in self.models:
                self.models.append(c.model)

    def find(self, model, system, build):
        return next((c for c in self.cells if c.model == model and c.system == system and c.build == build), None)

    def setting(self, name, default=NAN):
        return self.settings.get(name, default)


def thesis_rows(rows):
    """model -> {"thesis_model", "vertices", (stage, measure): value} (NaN = #over in the thesis)."""
    out = {}
    for r in rows:
        t = out.setdefault(r["model"], {"thesis_model": r["thesis_model"], "vertices": r["vertices"]})
        t[(r["stage"], r["measure"])] = number(r["value"])
    return out


def gemm(c):
    """Mean of the BLAS dgemm rates measured just before and after the cell (GFlop/s)."""
    b, a = c.get("blas_dgemm_before"), c.get("blas_dgemm_after")
    return b if isnan(a) else (b + a) / 2


def read_rate(c):
    b, a = c.get("memory_read_before"), c.get("memory_read_after")
    return b if isnan(a) else (b + a) / 2


def held(c):
    """(matrix name, bytes) of every matrix the build held, in the order of the CSV."""
    return [(m[len("held_bytes:"):], v) for m, v in c.values.items() if m.startswith("held_bytes:")]


def thesis_num(v, prec):
    return "#over" if isnan(v) else f"{v:.{prec}f}"


def cell_text(c, measure, prec, scale, mem):
    """A measured value (flagged when its repeats disagree), or the status with the prediction for cells that did not
    run."""
    if c is None:
        return "-"
    if c.ok():
        v = c.get(measure)
        timing = FLAG_OF.get(measure, measure)
        return "n/a" if isnan(v) else f"{v / scale:.{prec}f}" + (mark(c.get, timing) if timing.endswith("_s") else "")
    if c.status == "#over":
        return f"#over ({c.get('predicted_bytes') / MIB:.0f} pred.)"
    if c.status == "#slow":
        return (f"#slow ({c.get('predicted_bytes') / MIB:.0f} pred.)" if mem
                else f"#slow ({c.get('predicted_s'):.0f} s pred.)")
    return "error"


def ratio_text(a, b, suffix=""):
    if isnan(a) or isnan(b) or not a > 0 or not b > 0:
        return "-"
    return f"{a / b:.1f}x{suffix}"


def header(run):
    p, s = provenance(run.rows), run.setting
    mib = number(s("memory_budget_bytes")) / MIB
    out = ["# Thesis Table 2-1 reproduced: dense, naive sparse and structured sparse builds\n",
           f"Machine: {p.get('cpu')} ({p.get('hardware_threads')} hardware threads), {p.get('blas')} core "
           f"{p.get('blas_core')} ({p.get('blas_threads')} BLAS threads), git {p.get('git_sha')}, {p.get('timestamp')}.\n",
           f"Budgets: memory {mib:.0f} MiB per cell (checked against a prediction before a cell runs), time "
           f"{number(s('time_budget_s')):.0f} s per cell (predicted from flop counts at the rates measured at start: "
           f"dense GEMM {number(s('rate_dense_flops')) / 1e9:.1f} GFlop/s, sparse A^T A "
           f"{number(s('rate_sparse_flops')) / 1e9:.2f} GFlop/s, matrix-vector {number(s('rate_stream_flops')) / 1e9:.2f} "
           f"GFlop/s); a running cell is killed after {number(s('cell_timeout_s')):.0f} s. Frames per cell: "
           f"{s('frames')}; runs per cell: {s('repeats')} (fresh children, median of each measure; once when predicted "
           f"above {number(s('repeat_max_s')):.0f} s). Backend: {s('backend')} (ordering {s('ordering')}); the dense "
           f"build factors with {s('dense_backend')}.\n",
           "**The edit** (harness/thesis_edit.h): region of interest = the whole mesh; handle = the 100 vertices nearest "
           "the extreme vertex along the longest bounding-box axis, dragged by a translation of 0.2 x the bounding-box "
           "diagonal along the second-longest axis (frames interpolate it); 100 anchor vertices nearest the opposite "
           "extreme kept in place. Constraints are soft (thesis eq. 2-4, weight 1 after normalizing the mesh to a unit "
           "diagonal), so every vertex is an unknown: the LAP system is #V x #V, the TF system 3#V x 3#V.\n"]
    notes = sorted((k[len("edit:"):], v) for k, v in run.settings.items() if k.startswith("edit:"))
    out.append("".join(f"- {tier}: {note}\n" for tier, note in notes))
    out.append("**Measures**: memory = the cell child's own peak RSS (VmHWM, MiB = 2^20 bytes; as are the thesis' MB: its "
               "section 2.3 turns 36599062500 bytes into 34903, a division by 2^20); init = build + analyze + factorize; fps = 1 / median frame time (right-hand "
               "side + solve + positions written) over the frames of the drag. Handle mode (issue 16): after the drag the same factored system precomputes its responses to the handle's affine map (one multi-right-hand-side solve, `precompute`) and the drag runs again streaming them; fps = 1 / its median frame, and the cell records how far its last frame lies from the full mode's (`handle_vs_full`, in table_2_1.csv). `#over` / `#slow`: predicted over the "
               "memory / time budget, never attempted (the prediction is shown: MiB for #over, seconds for #slow).\n")
    return "\n".join(out)


def system_table(run, system):
    tf = system == "tf"
    out = [f"## {'TF' if tf else 'LAP'} system{' (the thesis' + chr(39) + ' table)' if tf else ' (no thesis numbers)'}\n"]
    if tf:
        out.append("| model | vertices thesis / ours | memory MB thesis before / after | peak RSS MiB ours dense / naive / "
                   "structured | init s thesis before / after | init s ours dense / naive / structured | fps thesis | "
                   "fps ours naive / structured | handle mode (structured): fps / init + precompute s |\n"
                   "|---|---|---|---|---|---|---|---|---|")
    else:
        out.append("| model | vertices | peak RSS MiB dense / naive / structured | init s dense / naive / structured | "
                   "fps dense / naive / structured | handle mode (structured): fps / init + precompute s |\n"
                   "|---|---|---|---|---|---|")
    for model in run.models:
        d, nv, st = (run.find(model, system, b) for b in ("dense", "naive", "structured"))
        if not (d or nv or st):
            continue
        any_ = st or nv or d
        verts = "?" if isnan(any_.vertices) else f"{any_.vertices:.0f}"
        mem = [cell_text(c, "peak_rss_bytes", 1, MIB, True) for c in (d, nv, st)]
        init = [cell_text(c, "init_s", 3, 1, False) for c in (d, nv, st)]
        fps = [cell_text(c, "fps", 1, 1, False) for c in (d, nv, st)]
        handle = f"{cell_text(st, 'fps_handle', 0, 1, False)} / {cell_text(st, 'init_precompute_s', 3, 1, False)}"
        if tf:
            t = run.thesis.get(model, {})
            tv = lambda stage, m, p: thesis_num(t.get((stage, m), NAN), p) if t else "-"  # noqa: E731
            out.append(f"| {model} | {t.get('vertices', '-')} / {verts} | {tv('before', 'memory_mb', 1)} / "
                       f"{tv('after', 'memory_mb', 1)} | {' / '.join(mem)} | {tv('before', 'init_s', 1)} / "
                       f"{tv('after', 'init_s', 1)} | {' / '.join(init)} | {tv('after', 'fps', 2)} | {fps[1]} / {fps[2]} | {handle} |")
        else:
            out.append(f"| {model} | {verts} | {' / '.join(mem)} | {' / '.join(init)} | {' / '.join(fps)} | {handle} |")
    return "\n".join(out) + "\n"


def dense_bytes(d):
    """Memory of a dense cell for the dense-vs-structured ratio: measured matrices + factor when it ran, else the
    prediction (predict_build_bytes already counts the LLT's copy of K); (bytes, predicted)."""
    if d is None:
        return NAN, False
    if d.ok():
        return d.get("held_total_bytes") + d.get("factor_bytes"), False
    return d.get("predicted_build_bytes"), True


def ratios(run):
    out = ["## Ratios\n\nstructured vs naive: matrices held before factorization (sum of held_bytes), build phase "
           "time, overall peak RSS of the cell. dense vs structured memory: (dense matrices + dense factor) / "
           "(structured matrices + sparse factor); for dense cells that did not run the dense side is the predicted "
           "bytes (marked p).\n\n| model | system | held naive/structured | build naive/structured | peak RSS "
           "naive/structured | dense/structured memory |\n|---|---|---|---|---|---|"]
    for model in run.models:
        for system in ("tf", "lap"):
            d, nv, st = (run.find(model, system, b) for b in ("dense", "naive", "structured"))
            if not st or not st.ok():
                continue
            n_ok = nv is not None and nv.ok()
            db, pred = dense_bytes(d)
            r = lambda m: ratio_text(nv.get(m), st.get(m)) if n_ok else "-"  # noqa: E731
            out.append(f"| {model} | {system} | {r('held_total_bytes')} | {r('build_s')} | {r('peak_rss_bytes')} | "
                       f"{ratio_text(db, st.get('held_total_bytes') + st.get('factor_bytes'), ' p' if pred else '')} |")
    return "\n".join(out) + "\n"


def memory_detail(run):
    out = ["## Memory in detail (MiB)\n\nExact bytes of every matrix the build held (by name), of the matrix handed "
           "to the solver and of the factor; the prediction the budget was checked against; the child's peak RSS "
           "(VmHWM) and wait4's ru_maxrss (which also counts the forked copy of the parent, shown as parent RSS).\n\n"
           "| model | system | build | n | held matrices | matrix | factor (pred.) | predicted total | peak RSS | "
           "ru_maxrss (parent) | status |\n|---|---|---|---|---|---|---|---|---|---|---|"]
    mib = lambda v: "-" if isnan(v) else f"{v / MIB:.1f}"  # noqa: E731
    for c in run.cells:
        h = ", ".join(f"{name} {b / MIB:.1f}" for name, b in held(c)) or "-"
        out.append(f"| {c.model} | {c.system} | {c.build} | {fmt(c.get('n'), '{:.0f}')} | {h} | "
                   f"{mib(c.get('matrix_bytes'))} | {mib(c.get('factor_bytes'))} ({mib(c.get('predicted_factor_bytes'))})"
                   f" | {mib(c.get('predicted_bytes'))} | {mib(c.get('peak_rss_bytes'))} | "
                   f"{mib(c.get('ru_maxrss_bytes'))} ({mib(c.get('parent_rss_bytes'))}) | {c.status} |")
    return "\n".join(out) + "\n"


def phase_times(run):
    out = ["## Phase times (s) and prediction\n\nEach timing is the median with its spread over the repeats, (least - "
           "largest, n = repeats): the runs of the cell for build, analyze, factorize and init; the frames of every run "
           "for the frames (rhs / solve / write: their medians). factorize GFlop/s: the factorization's flops over its "
           "time; BLAS dgemm: the rate of the BLAS's dgemm (1024^3, its own threads) measured by the driver just before "
           "and after the cell, their mean: the ceiling of the factorization's dense kernels at that moment; memory "
           "read: the rate the worker threads read a 128 MB array at, likewise (the solves stream the factor). "
           f"{rates_range(run.cells)}\n\n"
           "| model | system | build | build s | analyze s | factorize s | init s | frame s (rhs / solve / write) | "
           "handle frame s | predicted s | ordering | nnz(L) | factorize GFlop/s | BLAS dgemm GFlop/s | memory read "
           "GB/s |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    g = lambda v: fmt(v, "{:.4g}")  # noqa: E731
    for c in run.cells:
        f = c.get("factorize_s")
        rate = c.get("factor_flops") / f / 1e9 if c.ok() and f > 0 else NAN
        t = lambda m: f"{g(c.get(m))} {spread_text(c.get, m)}".strip()  # noqa: E731
        out.append(f"| {c.model} | {c.system} | {c.build} | {t('build_s')} | {t('analyze_s')} | {t('factorize_s')} | "
                   f"{t('init_s')} | {t('frame_s')} ({g(c.get('rhs_s'))} / {g(c.get('solve_s'))} / "
                   f"{g(c.get('write_s'))}) | {t('frame_handle_s')} | {g(c.get('predicted_s'))} | "
                   f"{c.ordering_used or '-'} | {fmt(c.get('nnz_factor'), '{:.0f}')} | {g(rate)} | {g(gemm(c))} | "
                   f"{g(read_rate(c))} |")
    table = "\n".join(out) + "\n"
    return table + spread_footnote(table)


def rates_range(cs):
    """How far the machine's rates moved over the cells of this run: the times move with them."""
    rates = lambda keys: [x for c in cs if c.ok() for x in map(c.get, keys) if not isnan(x)]  # noqa: E731
    g, r = rates(("blas_dgemm_before", "blas_dgemm_after")), rates(("memory_read_before", "memory_read_after"))
    if not g or not r:
        return "The run has no machine rates."
    return (f"Over this run's cells dgemm ran at {min(g):.3g} - {max(g):.3g} GFlop/s ({max(g) / min(g):.2g}x) and "
            f"memory read at {min(r):.3g} - {max(r):.3g} GB/s ({max(r) / min(r):.2g}x): the times in this table move "
            "with them.")


def spread_footnote(*tables):
    """The flag's meaning under tables, with how many of the timings they show carry it."""
    return f"\n{SPREAD_NOTE} Flagged here: {sum(t.count(FLAG) for t in tables)} timing(s).\n"


def init_why(c):
    """Where the init goes, and its floor with this build and ordering: the factorization's flops at the BLAS dgemm
    rate measured around the cell, the best its dense kernels could do on the machine as it was."""
    f, flops = c.get("factorize_s"), c.get("factor_flops")
    why = (f"build {c.get('build_s'):.2f} + analyze {c.get('analyze_s'):.2f} (ordering {c.ordering_used}) + factorize "
           f"{f:.2f} s ({flops / 1e9:.1f} GFlop at {flops / 1e9 / f if f > 0 else 0.0:.1f} GFlop/s)")
    g = gemm(c) * 1e9
    if not isnan(g) and g > 0 and f > 0:
        why += (f"; BLAS dgemm ran at {g / 1e9:.1f} GFlop/s around the cell: the factorization reached "
                f"{100 * flops / f / g:.0f}% of that, and at that rate throughout would still take {flops / g:.2f} s, "
                f"so init >= {c.get('build_s') + c.get('analyze_s') + flops / g:.2f} s with this build and ordering")
    return why


def frame_why(c):
    """Where a frame goes, and its floor: every frame's backward solve reads the whole factor once (the forward one
    redoes only the part the handle reaches), at best at the memory read rate measured around the cell."""
    why = (f"rhs {c.get('rhs_s') * 1e3:.1f} + solve {c.get('solve_s') * 1e3:.1f} + write {c.get('write_s') * 1e3:.1f} "
           f"ms (medians); the solve streams the {c.get('factor_bytes') / MIB:.0f} MiB factor")
    r = read_rate(c) * 1e9
    if not isnan(r) and r > 0:
        why += (f", which at the {r / 1e9:.1f} GB/s memory read rate measured around the cell takes "
                f"{1e3 * c.get('factor_bytes') / r:.1f} ms a pass")
    return why


def rss_why(c):
    return (f"factor {c.get('factor_bytes') / MIB:.0f} MiB; the build's matrices {c.get('held_total_bytes') / MIB:.0f} "
            f"MiB, handed back column range by column range as the factorization consumes them; the process before the "
            f"deformer {c.get('baseline_rss_bytes') / MIB:.0f} MiB")


def target(out, what, c, value, limit, at_most, unit, why, timed=None, scale=1.0):
    """A target's row, judged on the median (`value`); a timed one shows its spread over the repeats (`timed`: the
    measure, `scale` its unit)."""
    if c is None or not c.ok() or isnan(value):
        out.append(f"| {what} | {c.status if c else 'missing'} | - | {c.message if c else ''} |")
        return
    met = value <= limit if at_most else value >= limit
    spread = spread_text(c.get, timed, lambda x: f"{x * scale:.3g}") if timed else ""
    out.append(f"| {what} | {f'{value:.3g} {unit} {spread}'.strip()} | {'yes' if met else '**no**'} | {why} |")


def targets(run):
    out = ["## Targets at the 104k tier (planck = armadillo_loop1)\n\nA timed target is met when its median is; the "
           "spread beside it (least - largest, n = repeats) says whether every repeat was.\n\n| target | measured "
           "(median) | met | where it goes (same cells) |\n|---|---|---|---|"]
    tfs, tfn, lps = run.find("planck", "tf", "structured"), run.find("planck", "tf", "naive"), run.find("planck", "lap", "structured")
    ok = lambda c: c is not None and c.ok()  # noqa: E731
    v = lambda c, m, s=1.0: c.get(m) * s if ok(c) else NAN  # noqa: E731
    target(out, "TF structured init <= 2.0 s", tfs, v(tfs, "init_s"), 2.0, True, "s", init_why(tfs) if ok(tfs) else "",
           "init_s")
    target(out, "TF structured frame <= 100 ms", tfs, v(tfs, "frame_s", 1e3), 100, True, "ms",
           frame_why(tfs) if ok(tfs) else "", "frame_s", 1e3)
    target(out, "TF structured peak RSS <= 1.0 GB (10^9 B)", tfs, v(tfs, "peak_rss_bytes", 1e-9), 1.0, True, "GB",
           rss_why(tfs) if ok(tfs) else "")
    target(out, "LAP structured init <= 0.5 s", lps, v(lps, "init_s"), 0.5, True, "s", init_why(lps) if ok(lps) else "",
           "init_s")
    target(out, "LAP structured frame <= 25 ms", lps, v(lps, "frame_s", 1e3), 25, True, "ms",
           frame_why(lps) if ok(lps) else "", "frame_s", 1e3)
    both = ok(tfs) and ok(tfn)
    q = lambda m: tfn.get(m) / tfs.get(m) if both else NAN  # noqa: E731
    mib = lambda c, m: c.get(m) / MIB  # noqa: E731
    target(out, "TF held matrices naive/structured >= 3x", tfs if both else None, q("held_total_bytes"), 3, False, "x",
           f"naive {mib(tfn, 'held_total_bytes'):.0f} vs structured {mib(tfs, 'held_total_bytes'):.0f} MiB" if both else "")
    target(out, "TF build naive/structured >= 5x", tfs if both else None, q("build_s"), 5, False, "x",
           f"naive {tfn.get('build_s'):.2f} vs structured {tfs.get('build_s'):.2f} s (medians)" if both else "")
    at = dict(held(tfn)).get("At", 0.0) if both else 0.0
    target(out, "TF peak RSS naive/structured >= 1.5x", tfs if both else None, q("peak_rss_bytes"), 1.5, False, "x",
           f"naive {mib(tfn, 'peak_rss_bytes'):.0f} vs structured {mib(tfs, 'peak_rss_bytes'):.0f} MiB; the factor "
           f"(naive {mib(tfn, 'factor_bytes'):.0f}, structured {mib(tfs, 'factor_bytes'):.0f} MiB) is {100 * tfs.get('factor_bytes') / tfs.get('peak_rss_bytes'):.0f}% "
           f"of the structured peak; beside it the naive cell keeps A^T ({at / MIB:.0f} MiB) for its frames, as the "
           f"thesis' first version did" if both else "")
    big_target(run, out, ok)
    return "\n".join(out) + "\n"


def big_target(run, out, ok):
    """The 1.6M-vertex TF cell of the --full scaling series, against the memory budget it ran under."""
    big = None
    for c in run.scaling:
        if c.system == "tf" and c.vertices >= 1.6e6 and (big is None or c.vertices > big.vertices):
            big = c
    if big is None:
        return
    budget = number(run.setting("memory_budget_bytes")) / MIB
    disk = "on disk (out of core)" if big.factor_storage == "disk" else "in memory"
    bound = 10.0 * big.get("n") * 2.220446049250313e-16  # solvers' singular_pivot_bound: 10 n eps
    target(out, f"TF structured, {big.model} ({big.vertices:.0f} vertices), within the {budget:.0f} MiB budget", big,
           big.get("peak_rss_bytes") / MIB if ok(big) else NAN, budget, True, "MiB",
           f"factor {big.get('factor_bytes') / MIB:.0f} MiB {disk}; init {big.get('init_s'):.1f} s, frame "
           f"{big.get('frame_s'):.2f} s; smallest pivot {big.get('min_pivot_ratio'):.2g} of its diagonal entry "
           f"(singular-input bound 10 n eps = {bound:.2g})" if ok(big) else "")


def scaling(run):
    if not run.fits and not run.scaling:
        return ""
    out = ["## Scaling of the structured build (results/scaling.csv, scaling_fits.csv)\n\nCost ~ c * #V^k fitted by "
           "least squares in log-log space, on n >= 4 points (a series or measure with fewer has no fit).\n\n"
           "| series | system | measure | exponent k | r^2 | n | #V range |\n"
           "|---|---|---|---|---|---|---|"]
    for f in run.fits:
        out.append(f"| {f['series']} | {f['system']} | {f['measure']} | {number(f['exponent']):.2f} | "
                   f"{number(f['r2']):.3f} | {f['points']} | {number(f['vertices_min']):.0f} - "
                   f"{number(f['vertices_max']):.0f} |")
    out.append("\n| series | model | #V | system | init s | frame s | factor MiB | peak RSS MiB | status |\n"
               "|---|---|---|---|---|---|---|---|---|")
    for c in run.scaling:
        out.append(f"| {c.series} | {c.model} | {'?' if isnan(c.vertices) else f'{c.vertices:.0f}'} | {c.system} | "
                   f"{cell_text(c, 'init_s', 3, 1, False)} | {cell_text(c, 'frame_s', 4, 1, False)} | "
                   f"{cell_text(c, 'factor_bytes', 1, MIB, True)} | {cell_text(c, 'peak_rss_bytes', 1, MIB, True)} | "
                   f"{c.status}{'' if c.factor_storage != 'disk' else ' (factor on disk)'} |")
    table = "\n".join(out) + "\n"
    return table + spread_footnote(table)


def not_run(run):
    lines = [f"- {c.model}/{c.system}/{c.build}/{c.backend} ({c.status}): {c.message}"
             for c in run.cells + [s for s in run.scaling if s.series != "tiers"] if not c.ok()]
    return "## Cells that did not run\n\n" + ("\n".join(lines) if lines else "none") + "\n"


def init_spread_note(run):
    """How far apart a cell's fresh children put its init, over the cells that ran it more than once."""
    r = sorted(c.get("init_max_s") / c.get("init_min_s") for c in run.cells + run.scaling
               if c.ok() and c.get("init_reps") > 1 and c.get("init_min_s") > 0)
    p = provenance(run.rows)
    where = f"On this machine ({p.get('hardware_threads')} hardware threads) the"
    if not r:
        return f"{where} cells ran once each: no spread of the init between runs."
    return (f"{where} largest / least init of a cell's children was {r[0]:.2f} - {r[-1]:.2f}x (median "
            f"{median(r):.2f}x over {len(r)} cells): compare init times at that resolution.")


def notes(run):
    return NOTES.format(init_spread=init_spread_note(run))


NOTES = """## Notes

- Init is measured once per run of a cell; the table takes the median of --repeats fresh children; frame times are \
medians over the drag (of the runs' medians). {init_spread} The phase table gives every timing's spread; the flag \
under the tables marks a timing whose repeats disagree (fps: its frame's).
- Thesis vertex counts differ from the bundled meshes (the thesis' models are not available); the planck tier is \
armadillo Loop-subdivided once, the horse tier CGAL's refined_elephant.
- The sparse factor prediction comes from a symbolic analysis of the vertex-level 2-ring graph (for TF expanded to 3x3 \
blocks; flops scaled by 27), not from the exact scalar pattern: compare `factor (pred.)` above.
- ru_maxrss of a child counts the parent's forked image (Linux folds the pre-exec high-water mark in), so peak RSS \
here is the child's own VmHWM.
"""


def write(results):
    """Writes RESULTS/table_2_1.md; False when there is no table_2_1.csv."""
    run = Run(results)
    if not run.cells:
        return False
    tf, lap = system_table(run, "tf"), system_table(run, "lap")
    parts = [header(run), tf, lap, spread_footnote(tf, lap), ratios(run), memory_detail(run), phase_times(run),
             targets(run), scaling(run), not_run(run), notes(run)]
    write_atomically(os.path.join(results, "table_2_1.md"), "\n".join(p for p in parts if p))
    return True
