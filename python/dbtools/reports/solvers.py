"""results/solvers.md from the CSVs exp_solvers wrote (solvers.csv, and solvers_blas_*.csv: the same driver under
other OPENBLAS_CORETYPE values): the verdict on the thesis' claim that Cholesky is slightly faster than LU and
Bunch-Kaufman, least squares on A against the normal equations, every backend, the orderings, the fastest choice
per tier (first, with its memory and accuracy), the thread counts (--threads) and the BLAS kernel sets. Reads CSVs
only, never measures."""
import os

from .common import (MIB, NAN, SPREAD_NOTE, cells, count_flagged, fmt, geomean, isnan, mark, median, minmax, number,
                    provenance, read_rows, spread_text, write_atomically)
from .kernel_sets import kernel_sets

KEY = ("model", "system", "backend", "family", "ordering", "ordering_used", "threads", "thread_env")
# The summary reads the minimum over a cell's repetitions: on a shared machine interference only adds time.
FACTOR, SOLVE = "factorize_min_s", "solve_min_s"


def thread_count(c):
    return number(c.threads) if getattr(c, "threads", "") else NAN


class Run:
    def __init__(self, rows):
        self.rows = rows
        self.all_cells = cells(rows, KEY)
        # Every section but the threads one reads each cell at its smallest thread count (the study's --threads
        # runs every cell at each count).
        self.counts = sorted({thread_count(c) for c in self.all_cells if not isnan(thread_count(c))})
        self.cells = [c for c in self.all_cells if isnan(thread_count(c)) or thread_count(c) == self.counts[0]]
        self.models, self.systems, self.backends = [], [], []
        for c in self.cells:
            for lst, v in ((self.models, c.model), (self.systems, c.system), (self.backends, c.backend)):
                if v not in lst:
                    lst.append(v)

    def find(self, model, system, backend, ordering="default"):
        return next((c for c in self.cells if (c.model, c.system, c.backend, c.ordering) ==
                     (model, system, backend, ordering)), None)

    def best(self, model, system, pred):
        """The ok cell of a tier and system with the least factorize time among those `pred` accepts."""
        best = None
        for c in self.cells:
            if c.model == model and c.system == system and c.ok() and pred(c):
                if best is None or c.get(FACTOR) < best.get(FACTOR):
                    best = c
        return best


def value(c, m):
    return c.get(m) if c is not None and c.ok() else NAN


def fsec(x):
    if isnan(x):
        return "-"
    if x < 1e-3:
        return f"{x * 1e6:.1f} us"
    if x < 1:
        return f"{x * 1e3:.2f} ms"
    return f"{x:.2f} s"


def fratio(a, b):
    return f"{a / b:.2f}" if not isnan(a) and not isnan(b) and a > 0 and b > 0 else "-"


def rng(v):
    lo, hi = minmax(v)
    return "-" if isnan(lo) else f"{lo:.2f}-{hi:.2f}"


def verdict_word(g):
    if isnan(g):
        return "not measured"
    if g < 0.95:
        return "**refuted** (Cholesky is slower)"
    if g < 1.05:
        return "**no measurable difference** (within 5%)"
    if g < 1.5:
        return "**confirmed**: Cholesky is slightly faster"
    return "**confirmed, and understated**: Cholesky is clearly faster, not just slightly"


def verdict_prose(g_lu, g_bk, g_sparse, lu, bk, sparse):
    """One paragraph stating the measured verdict from the ratios (> 1: Cholesky faster)."""
    def all_above(v, t):
        v = [x for x in v if not isnan(x)]
        return bool(v) and all(x > t for x in v)
    s = "**Measured verdict.** "
    if isnan(g_lu) and isnan(g_sparse):
        return s + "Not measured (no Cholesky / LU pair ran)."
    holds = all_above(lu, 1.0) and all_above(bk, 1.0) and all_above(sparse, 1.0)
    s += ("The claim holds on every system measured: Cholesky factorizes faster than LU and than Bunch-Kaufman. "
          if holds else "The claim does not hold on every system measured (see the ranges). ")
    gap = min(x for x in (g_lu, g_sparse) if not isnan(x)) if not (isnan(g_lu) and isnan(g_sparse)) else NAN
    s += (f"{'Against LU the gap is larger than ' + chr(34) + 'slightly' + chr(34) if gap >= 1.5 else 'Against LU'}: "
          f"dense LU took {fmt(g_lu, '{:.2f}')}x the time of dense Cholesky and the fastest sparse LU "
          f"{fmt(g_sparse, '{:.2f}')}x the fastest sparse Cholesky (geometric means), as expected from LU's doubled "
          "flop count (dense: 2n^3/3 against n^3/3) and its doubled factor (L and U). ")
    s += (f"Bunch-Kaufman LDL^T does the same n^3/3 flops as Cholesky; its {fmt(g_bk, '{:.2f}')}x comes from the "
          "symmetric pivot search and the less regular blocking of dsytrf"
          + (", and is where \"slightly\" fits." if g_bk < 1.5 else ": clearly slower as well, not slightly."))
    return s


def header(run, p):
    loads = [c.get("load_avg_1m") for c in run.cells if not isnan(c.get("load_avg_1m"))]
    load_med, load_max = median(loads), (max(loads) if loads else NAN)
    reps = lambda m: max((c.get(m) for c in run.cells if not isnan(c.get(m))), default=NAN)  # noqa: E731
    hw = number(p.get("hardware_threads"))
    out = ["# Solver choice for the LAP and TF systems (issue 4)\n",
           "Generated by the report step (dbtools/reports/solvers.py) from `results/solvers.csv` (exp_solvers, "
           "experiments/solvers.cpp); do not edit by hand.\n",
           "- Systems: the thesis edit of every tier (whole-mesh ROI, 100 handle vertices at one extreme of the longest "
           "axis, 100 anchors at the other), soft constraints (w = 1), structured build: K is #V x #V (lap, 3 "
           "right-hand-side columns) or 3#V x 3#V (tf, 1 column). `spqr` solves the least-squares problem on the naive "
           "build's A itself (QR, A^T A never formed). A run with `--edit` has that edit's systems instead (its "
           "method, constraints and weights; lri: `lri-frames` and `lri-positions`), one with `--matrix` the system "
           "of that file (`matrix`).",
           f"- Every cell (tier, system, backend, ordering) ran in its own child process: peak RSS is that process' "
           "VmHWM (mesh + system + solver). Factorize and solve (of the deformation's right-hand side) repeat up to "
           "--factor-reps / --solve-reps times, each phase no longer than --rep-seconds; from three repetitions on the "
           "first warms up and the spread leaves it out: up to "
           f"{fmt(reps('factorize_reps'), '{:.0f}')} factorizations and {fmt(reps('solve_reps'), '{:.0f}')} solves "
           "counted. Tables below show the minimum of those (interference from other jobs only adds time; the CSV has "
           "the medians too, `factorize_s`, `solve_s`, and the largest, `factorize_max_s`, `solve_max_s`). "
           "One thread (BLAS, OpenMP, assembly) unless `--threads`.",
           "- Errors: `residual` = ||Kx-b||/||b|| (deformation RHS); `error_exact` = ||x-x_ref||/||x_ref|| for "
           "b = K x_ref (spqr: b = A x_ref) with a seeded random x_ref; `error_vs_cholmod` = deformed positions against "
           "CHOLMOD supernodal (default ordering) of the same system.",
           f"- Machine: {p.get('cpu')}; {p.get('hardware_threads')} threads; {p.get('compiler')}; BLAS {p.get('blas')} "
           f"core {p.get('blas_core')} (OPENBLAS_CORETYPE={'unset' if p.get('blas_coretype_env') in ('', 'auto') else p.get('blas_coretype_env')}), "
           f"{p.get('blas_threads')} BLAS threads; git {p.get('git_sha')}."]
    if isnan(load_med):
        out.append("- Load average: not recorded.\n")
    else:
        busy = load_med > 0.5 * hw
        out.append(f"- Load average (1 min) before each cell: median {load_med:.1f}, max {load_max:.1f}, on "
                   f"{p.get('hardware_threads')} hardware threads"
                   + (": the machine was shared with other jobs, so single timings carry noise of tens of percent; "
                      "ratios within 0.8-1.25 are not significant.\n" if busy else ".\n"))
    return "\n".join(out)


def dense_table(run, lu, bk):
    """Dense factorizations of the same matrix with the same BLAS; appends the LU/LL^T and BK/LL^T ratios."""
    out = ["### Dense factorizations (same matrix, same BLAS)\n\n| tier | system | n | LAPACK dpotrf (LL^T) | Eigen LLT | "
           "LAPACK dsytrf (Bunch-Kaufman LDL^T) | LAPACK dgetrf (LU) | LU / LL^T | BK / LL^T | Eigen LLT / dpotrf |\n"
           "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    any_dense = False
    for m in run.models:
        for sys in run.systems:
            pot, llt, b, u = (run.find(m, sys, x) for x in ("lapack_potrf", "dense_llt", "dense_ldlt_bk", "dense_lu"))
            tp, tl, tb, tu = (value(c, FACTOR) for c in (pot, llt, b, u))
            if all(isnan(x) for x in (tp, tl, tb, tu)):
                continue
            any_dense = True
            chol = tl if isnan(tp) else tp  # same-library Cholesky when measured
            lu.append(tu / chol)
            bk.append(tb / chol)
            n = value(u if u is not None else pot, "n")
            out.append(f"| {m} | {sys} | {fmt(n, '{:.0f}')} | {fsec(tp)} | {fsec(tl)} | {fsec(tb)} | {fsec(tu)} | "
                       f"{fratio(tu, chol)} | {fratio(tb, chol)} | {fratio(tl, tp)} |")
    if not any_dense:
        out.append("| (no dense cell ran: every tier is over --dense-max-n) | | | | | | | | | |")
    out.append("\nRatios are factorize-time quotients (> 1: Cholesky faster). Flop counts: LL^T and LDL^T n^3/3, "
               "LU 2n^3/3.\n")
    return "\n".join(out)


def with_ordering(c):
    return f"{fsec(c.get(FACTOR))} ({c.ordering})" if c is not None and c.ok() else "-"


def sparse_table(run, cm_ratio, eig_ratio, any_ratio):
    """Each sparse backend at its default ordering and at its best measured one (an LU code given an ordering meant
    for Cholesky, e.g. AMD for SparseLU, is not a fair opponent); appends the LU/Cholesky ratios of the best."""
    out = ["### Sparse factorizations (same matrix)\n\n`default`: each backend with its own default ordering; `best`: "
           "each backend with the ordering that factorized fastest among those measured (in parentheses).\n\n| tier | "
           "system | n | orderings | CHOLMOD supernodal | Eigen simplicial LL^T | UMFPACK | Eigen SparseLU | UMFPACK / "
           "CHOLMOD | SparseLU / Eigen LL^T | nnz(L+U) / nnz(L), UMFPACK / CHOLMOD |\n"
           "|---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|"]
    names = ("cholmod_supernodal", "eigen_simplicial_llt", "umfpack", "eigen_sparse_lu")
    for m in run.models:
        for sys in run.systems:
            for best in (False, True):
                cm, el, um, sl = (run.best(m, sys, lambda c, b=b: c.backend == b) if best else run.find(m, sys, b)
                                  for b in names)
                tc, te, tu, ts = (value(c, FACTOR) for c in (cm, el, um, sl))
                if all(isnan(x) for x in (tc, te, tu, ts)):
                    continue
                if best:
                    cm_ratio.append(tu / tc)
                    eig_ratio.append(ts / te)
                    bl = run.best(m, sys, lambda c: c.family == "sparse-lu")
                    bc = run.best(m, sys, lambda c: c.family == "sparse-cholesky")
                    any_ratio.append(value(bl, FACTOR) / value(bc, FACTOR))
                n = value(cm if cm is not None else um, "n")
                out.append(f"| {m} | {sys} | {fmt(n, '{:.0f}')} | {'best' if best else 'default'} | {with_ordering(cm)} | "
                           f"{with_ordering(el)} | {with_ordering(um)} | {with_ordering(sl)} | {fratio(tu, tc)} | "
                           f"{fratio(ts, te)} | {fratio(value(um, 'nnz_factor'), value(cm, 'nnz_factor'))} |")
    out.append("\nCHOLMOD / Eigen LL^T store L only; UMFPACK and SparseLU store L and U (nnz counts both).\n")
    return "\n".join(out)


def verdict(run):
    lu, bk, cm, eig, any_ = [], [], [], [], []
    dense, sparse = dense_table(run, lu, bk), sparse_table(run, cm, eig, any_)
    g_lu, g_bk, g_cm, g_eig, g_any = (geomean(v) for v in (lu, bk, cm, eig, any_))
    rows = [("dense LU / dense Cholesky", g_lu, lu), ("dense Bunch-Kaufman LDL^T / dense Cholesky", g_bk, bk),
            ("sparse UMFPACK LU / CHOLMOD supernodal LL^T (best orderings)", g_cm, cm),
            ("sparse Eigen SparseLU / Eigen simplicial LL^T (best orderings)", g_eig, eig),
            ("fastest sparse LU / fastest sparse Cholesky (any backend, any ordering)", g_any, any_)]
    out = ["## Verdict on the thesis' claim (section 2.2.3: Cholesky is slightly faster than LU and Bunch-Kaufman)\n",
           "| comparison | factorize-time ratio (geometric mean) | range over systems | verdict |\n|---|---:|---:|---|"]
    out += [f"| {name} | {fmt(g, '{:.2f}')} | {rng(v)} | {verdict_word(g)} |" for name, g, v in rows]
    out += ["", verdict_prose(g_lu, g_bk, g_any, lu, bk, any_), "",
            "Dense Cholesky is LAPACK dpotrf where it ran (same library as dgetrf / dsytrf), else Eigen's LLT. The "
            "thesis measured on an AMD64 3000+ (2008) without saying which implementations it compared.\n",
            dense, sparse]
    return "\n".join(out)


def least_squares(run):
    """QR of A (spqr) against Cholesky of A^T A (the reference): accuracy on the same systems, time, memory."""
    out = ["## Least squares on A (SPQR) against the normal equations\n\n`spqr` factors the naive build's A itself "
           "(QR; A^T A is never formed, so the condition number is not squared); the reference is CHOLMOD supernodal on "
           "K = A^T A. `error_exact`: ||x - x_ref|| / ||x_ref|| for a right-hand side with a known solution; time: "
           "factorize + one solve (QR's analysis is part of its factorize); memory: the factor and the cell's peak RSS."
           "\n\n| tier | system | n | error_exact QR / Cholesky | vs CHOLMOD | residual QR / Cholesky | factorize + solve QR "
           "/ Cholesky | factor MiB QR / Cholesky | peak RSS MiB QR / Cholesky | status |\n"
           "|---|---|---:|---:|---:|---:|---:|---:|---:|---|"]
    any_ = False
    for m in run.models:
        for sys in run.systems:
            q, c = run.find(m, sys, "spqr"), run.find(m, sys, "cholmod_supernodal")
            if q is None:
                continue
            any_ = True
            t = lambda x: value(x, "analyze_s") + value(x, FACTOR) + value(x, SOLVE)  # noqa: E731
            pair = lambda a, b, f: f"{f(a)} / {f(b)}"  # noqa: E731
            e = lambda x: fmt(x, "{:.1e}")  # noqa: E731
            mib = lambda x: fmt(x / MIB, "{:.1f}")  # noqa: E731
            out.append(f"| {m} | {sys} | {fmt(value(q, 'n'), '{:.0f}')} | "
                       f"{pair(value(q, 'error_exact'), value(c, 'error_exact'), e)} | {e(value(q, 'error_vs_cholmod'))} | "
                       f"{pair(value(q, 'residual'), value(c, 'residual'), e)} | {pair(t(q), t(c), fsec)} | "
                       f"{pair(value(q, 'factor_bytes'), value(c, 'factor_bytes'), mib)} | "
                       f"{pair(value(q, 'peak_rss_bytes'), value(c, 'peak_rss_bytes'), mib)} | "
                       f"{'ok' if q.ok() else q.message} |")
    return "\n".join(out) + "\n\n" + least_squares_verdict(run) + "\n" if any_ else ""


def least_squares_verdict(run):
    """The ratios QR / Cholesky over the systems where both ran (geometric means, per system)."""
    lines = []
    for sys in run.systems:
        err, time, rss = [], [], []
        for m in run.models:
            q, c = run.find(m, sys, "spqr"), run.find(m, sys, "cholmod_supernodal")
            if q is None or c is None or not q.ok() or not c.ok():
                continue
            err.append(c.get("error_exact") / q.get("error_exact"))
            time.append((q.get(FACTOR) + q.get(SOLVE)) / (c.get("analyze_s") + c.get(FACTOR) + c.get(SOLVE)))
            rss.append(q.get("peak_rss_bytes") / c.get("peak_rss_bytes"))
        if err:
            lines.append(f"{sys}: Cholesky's error is {fmt(geomean(err), '{:.3g}')}x QR's (range {rng(err)}), at "
                         f"{fmt(geomean(time), '{:.2f}')}x the time (factorize + solve; range {rng(time)}) and "
                         f"{fmt(geomean(rss), '{:.2f}')}x the peak memory (range {rng(rss)}) for QR")
    if not lines:
        return ""
    return ("**Measured.** " + "; ".join(lines) + ". Where the normal equations square an ill-conditioned system "
            "(TF), QR keeps digits Cholesky loses, so `vs CHOLMOD` above is mostly Cholesky's own error; QR costs "
            "more time and memory, and more per frame (its solve applies Q^T to the stacked right-hand side).")


def every_backend(run):
    out = ["## Every backend, default ordering\n\n| tier | system | n | backend | ordering used | analyze | factorize | "
           "solve | nnz(L) | GFlop/s | factor MiB | peak RSS MiB | residual | error_exact | vs CHOLMOD | status |\n"
           "|---|---|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
    for m in run.models:
        for sys in run.systems:
            for be in run.backends:
                r = run.find(m, sys, be)
                if r is None:
                    continue
                v = lambda k: value(r, k)  # noqa: E731
                sp = lambda k: spread_text(r.get, k, fsec) if r.ok() else ""  # noqa: E731
                out.append(f"| {m} | {sys} | {fmt(r.get('n'), '{:.0f}')} | {be} | {r.ordering_used or '-'} | "
                           f"{fsec(v('analyze_s'))} | {fsec(v(FACTOR))} {sp('factorize_s')} | "
                           f"{fsec(v(SOLVE))} {sp('solve_s')} | "
                           f"{fmt(v('nnz_factor'), '{:.0f}')} | {fmt(v('gflops'), '{:.2f}')} | "
                           f"{fmt(v('factor_bytes') / MIB, '{:.1f}')} | {fmt(v('peak_rss_bytes') / MIB, '{:.0f}')} | "
                           f"{fmt(v('residual'), '{:.1e}')} | {fmt(v('error_exact'), '{:.1e}')} | "
                           f"{fmt(v('error_vs_cholmod'), '{:.1e}')} | {'ok' if r.ok() else r.message} |")
    ok = [c.get for c in run.cells if c.ok() and c.ordering == "default"]
    return ("\n".join(out) + "\n\nfactorize, solve: the least repetition with the spread (least - largest, n = "
            f"repetitions).\n\n{SPREAD_NOTE} Flagged here: {count_flagged(ok, ['factorize_s', 'solve_s'])} timing(s).\n")


def mixed_precision(run):
    """multifrontal_mixed against multifrontal (double) and multifrontal_refined per tier and system: factor bytes,
    peak RSS, times, CG iterations and the largest coordinate differences from the double and the refined cells
    (error_vs_double, error_vs_refined; diagonals). A tier may have the mixed row alone (a level whose double factor
    does not fit)."""
    out = ["## Mixed precision (multifrontal_mixed against multifrontal and multifrontal_refined)\n\n| tier | system | "
           "factor MiB double | factor MiB mixed | peak RSS MiB double | peak RSS MiB mixed | factorize double | "
           "factorize mixed | solve double | solve refined | solve mixed | CG iterations refined | CG iterations mixed | "
           "refined vs double | mixed vs double | mixed vs refined | status |\n"
           "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
    any_ = False
    for m in run.models:
        for sys in run.systems:
            d, f, x = (run.find(m, sys, b) for b in ("multifrontal", "multifrontal_refined", "multifrontal_mixed"))
            if x is None:
                continue
            any_ = True
            out.append(f"| {m} | {sys} | {fmt(value(d, 'factor_bytes') / MIB, '{:.1f}')} | "
                       f"{fmt(value(x, 'factor_bytes') / MIB, '{:.1f}')} | "
                       f"{fmt(value(d, 'peak_rss_bytes') / MIB, '{:.0f}')} | "
                       f"{fmt(value(x, 'peak_rss_bytes') / MIB, '{:.0f}')} | {fsec(value(d, FACTOR))} | "
                       f"{fsec(value(x, FACTOR))} | {fsec(value(d, SOLVE))} | {fsec(value(f, SOLVE))} | "
                       f"{fsec(value(x, SOLVE))} | {fmt(value(f, 'iterations'), '{:.0f}')} | "
                       f"{fmt(value(x, 'iterations'), '{:.0f}')} | {fmt(value(f, 'error_vs_double'), '{:.1e}')} | "
                       f"{fmt(value(x, 'error_vs_double'), '{:.1e}')} | {fmt(value(x, 'error_vs_refined'), '{:.1e}')} | "
                       f"{'ok' if x.ok() else x.message} |")
    note = ("\nThe double solve is not the exact one: on the TF systems it lies ~cond(K) eps from it, and the refined "
            "solves (double-double residuals) are the exact solution to their tolerance (`results/records/2026-11-24-tf-init-levers/`): "
            "mixed vs refined is what the float factor leaves.\n")
    return "\n".join(out) + "\n" + note if any_ else ""


def orderings(run):
    big = run.models[-1] if run.models else ""
    out = ["## Orderings (sparse direct backends, largest tier)\n\n| system | backend | ordering | ordering used | analyze "
           "| factorize | solve | nnz(L) | status |\n|---|---|---|---|---:|---:|---:|---:|---|"]
    for sys in run.systems:
        for r in run.cells:
            if r.model == big and r.system == sys and r.family in ("sparse-cholesky", "sparse-lu"):
                out.append(f"| {sys} | {r.backend} | {r.ordering} | {r.ordering_used or '-'} | "
                           f"{fsec(value(r, 'analyze_s'))} | {fsec(value(r, FACTOR))}{mark(r.get, 'factorize_s')} | "
                           f"{fsec(value(r, SOLVE))}{mark(r.get, 'solve_s')} | "
                           f"{fmt(value(r, 'nnz_factor'), '{:.0f}')} | {'ok' if r.ok() else r.message} |")
    return "\n".join(out) + "\n"


def accuracy(c):
    """The distance from the refined (exact to its tolerance) solution where measured, else error_exact."""
    e = value(c, "error_vs_refined")
    return (fmt(e, "{:.1e}") + " (vs refined)") if not isnan(e) else (fmt(value(c, "error_exact"), "{:.1e}") + " (exact)")


def fastest(run):
    """Best (backend, ordering) per system and tier for the interactive split (factorize once, solve per frame),
    with what it costs in memory and what it gives in accuracy; then the fastest factorize and solve, and the
    smallest peak RSS."""
    at = f" at {run.counts[0]:.0f} thread(s)" if run.counts else ""
    out = [f"## Fastest choice per tier and system{at}\n\n| tier | system | fastest analyze+factorize+20 solves "
           "(backend/ordering) | time | peak RSS MiB | factor MiB | error | fastest factorize | time | fastest solve "
           "| time | least peak RSS | MiB |\n|---|---|---|---:|---:|---:|---|---|---:|---|---:|---|---:|"]
    name = lambda c: f"{c.backend}/{c.ordering}" if c is not None else "-"  # noqa: E731
    mib = lambda c, k: fmt(value(c, k) / MIB, "{:.1f}") if c is not None else "-"  # noqa: E731
    for m in run.models:
        for sys in run.systems:
            ok = [c for c in run.cells if c.model == m and c.system == sys and c.ok()]
            if not ok:
                continue
            total = lambda c: c.get("analyze_s") + c.get(FACTOR) + 20 * c.get(SOLVE)  # noqa: E731
            pick = lambda cs, f: min(cs, key=f) if cs else None  # noqa: E731
            bf = pick([c for c in ok if c.family != "iterative"], lambda c: c.get(FACTOR))
            bs, bt, bm = pick(ok, lambda c: c.get(SOLVE)), pick(ok, total), pick(ok, lambda c: c.get("peak_rss_bytes"))
            out.append(f"| {m} | {sys} | {name(bt)} | {fsec(total(bt))} | {mib(bt, 'peak_rss_bytes')} | "
                       f"{mib(bt, 'factor_bytes')} | {accuracy(bt)} | {name(bf)} | "
                       f"{fsec(bf.get(FACTOR)) if bf else '-'} | {name(bs)} | {fsec(bs.get(SOLVE))} | {name(bm)} | "
                       f"{mib(bm, 'peak_rss_bytes')} |")
    out.append("\nerror: the largest coordinate difference from the multifrontal_refined cell's solution (bounding-box "
               "diagonals; `vs refined`) where that cell ran, else `error_exact` (||x - x_ref|| / ||x_ref|| for a "
               "right-hand side with a known solution).\n")
    return "\n".join(out) + "\n"


def threads(run):
    """Each cell at each thread count (--threads): factorize time, GFlop/s (factor flops / fastest factorize) and
    parallel efficiency against the smallest count, with the threading each layer got (harness/thread_policy.h)."""
    if len(run.counts) < 2:
        return ""
    out = ["## Threads\n\nEvery cell ran at each count; `thread env`: the OpenMP, BLAS and project (assembly, "
           "multifrontal tasks) threads the harness gave the backend. speedup = factorize at the smallest count / "
           f"factorize here; efficiency = speedup x {run.counts[0]:.0f} / threads.\n\n| tier | system | backend | "
           "ordering | threads | thread env | factorize | GFlop/s | speedup | efficiency | status |\n"
           "|---|---|---|---|---:|---|---:|---:|---:|---:|---|"]
    for c in run.all_cells:
        if c.family not in ("sparse-cholesky", "sparse-lu", "dense", "least-squares"):
            continue
        out.append(f"| {c.model} | {c.system} | {c.backend} | {c.ordering} | {c.threads} | {c.thread_env} | "
                   f"{fsec(value(c, FACTOR))} | {fmt(value(c, 'gflops'), '{:.2f}')} | "
                   f"{fmt(value(c, 'speedup'), '{:.2f}')} | {fmt(value(c, 'parallel_efficiency'), '{:.2f}')} | "
                   f"{'ok' if c.ok() else c.message} |")
    return "\n".join(out) + "\n"


def variant_section(run, path):
    """One BLAS kernel set run (solvers_blas_*.csv) against this run: factorize and solve ratios, with Eigen's dense
    LLT (which never calls the BLAS) as the control whose spread is the noise."""
    rows = read_rows(path)
    p = provenance(rows)
    vals = {(r["model"], r["system"], r["backend"], r["ordering"], r["measure"]): number(r["value"])
            for r in rows if r["status"] == "ok" and r["value"] != ""}
    out = [f"### {p.get('blas')} core {p.get('blas_core')} (OPENBLAS_CORETYPE={p.get('blas_coretype_env')}), "
           f"`{os.path.basename(path)}`\n\n| tier | system | backend | factorize here | factorize variant | ratio | solve "
           "here | solve variant | ratio |\n|---|---|---|---:|---:|---:|---:|---:|---:|"]
    blas, ctrl, dense, sparse = [], [], [], []
    for r in run.cells:
        k = (r.model, r.system, r.backend, r.ordering)
        if r.ordering != "default" or not r.ok() or k + (FACTOR,) not in vals:
            continue
        f0, s0, f1, s1 = r.get(FACTOR), r.get(SOLVE), vals[k + (FACTOR,)], vals.get(k + (SOLVE,), NAN)
        (ctrl if r.backend == "dense_llt" else blas).append(f1 / f0)
        if r.backend != "dense_llt":
            (dense if r.family == "dense" else sparse).append(f1 / f0)
        out.append(f"| {r.model} | {r.system} | {r.backend} | {fsec(f0)} | {fsec(f1)} | {fratio(f1, f0)} | {fsec(s0)} | "
                   f"{fsec(s1)} | {fratio(s1, s0)} |")
    gb = geomean(blas)
    clo, chi = minmax(ctrl)
    # Noise band: the no-BLAS control's spread, widened to at least +-20% (the control has few cells).
    lo, hi = min(1.0 if isnan(clo) else clo, 1 / 1.2), max(1.0 if isnan(chi) else chi, 1.2)
    if isnan(gb):
        v = "not measured"
    elif lo <= gb <= hi:
        v = (f"no measurable difference: the ratio lies inside the noise band {lo:.2f}-{hi:.2f} (the no-BLAS control's "
             "spread, at least +-20%)")
    else:
        v = f"{p.get('blas_core')} is {'faster' if gb < 1 else 'slower'} (outside the noise band {lo:.2f}-{hi:.2f})"
    out.append(f"\nFactorize ratio, geometric mean over the BLAS-calling cells: **{fmt(gb, '{:.2f}')}** (range "
               f"{rng(blas)}); Eigen LLT control (no BLAS): {fmt(geomean(ctrl), '{:.2f}')} (range {rng(ctrl)}). "
               f"Verdict: {v}.\n\nBy family: dense LAPACK (dpotrf, dsytrf, dgetrf) {fmt(geomean(dense), '{:.2f}')} "
               f"(range {rng(dense)}); sparse (CHOLMOD supernodal, UMFPACK) {fmt(geomean(sparse), '{:.2f}')} (range "
               f"{rng(sparse)}).\n")
    return "\n".join(out)


def blas(run, p, results):
    core = p.get("blas_coretype_env")
    out = ["## BLAS kernel set\n",
           f"This run: {p.get('blas')} core **{p.get('blas_core')}** (OPENBLAS_CORETYPE="
           f"{'unset, auto-detected' if core in ('', 'auto') else core}). "]
    distinct, duplicates = kernel_sets(results)
    first = {k: c for c, k, _ in distinct}  # kernel set -> the core of the run that has it
    same = "".join(f" `{os.path.basename(path)}` reports core {c}, which loads the {k} kernels of the {first[k]} run: "
                   "left out (data/experiments/blas_kernel_sets.txt)." for c, k, path in duplicates)
    if len(distinct) < 2:
        out[-1] += ("No other kernel set was measured, so there is no kernel comparison (scripts/experiments.sh "
                    "runs the BLAS-calling backends again under each OPENBLAS_CORETYPE whose reported core loads "
                    "another kernel set than this run's: SkylakeX where the CPU has avx512f, Haswell, "
                    f"auto-detection).{same}\n")
        return "\n".join(out)
    out[-1] += ("The same driver was run again with other `OPENBLAS_CORETYPE` values, restricted to the backends that "
                "call the BLAS (CHOLMOD supernodal, UMFPACK, LAPACK dense) plus Eigen's own dense LLT as a control (it "
                "never calls the BLAS, so its ratio shows the run-to-run noise). Ratio = variant time / this run's time "
                f"(< 1: the variant is faster).{same}\n")
    return "\n".join(out + [variant_section(run, path) for _, _, path in distinct[1:]])


def write(results):
    """Writes RESULTS/solvers.md; False when there is no solvers.csv."""
    rows = read_rows(os.path.join(results, "solvers.csv"))
    if not rows:
        return False
    run, p = Run(rows), provenance(rows)
    parts = [header(run, p), fastest(run), verdict(run), least_squares(run), every_backend(run), mixed_precision(run),
             orderings(run), threads(run), blas(run, p, results)]
    write_atomically(os.path.join(results, "solvers.md"), "\n".join(x for x in parts if x))
    return True
