"""results/solvers.md from the CSVs exp_solvers wrote (solvers.csv, and solvers_blas_*.csv: the same driver under
other OPENBLAS_CORETYPE values): the verdict on the thesis' claim that Cholesky is slightly faster than LU and
Bunch-Kaufman, least squares on A against the normal equations, every backend, the orderings, the fastest choice
per tier (first, with its memory and accuracy), the thread counts (--threads) and the BLAS kernel sets. Reads CSVs
only, never measures."""
import math
import os
import statistics

from .common import (FLAG, MIB, NAN, SPREAD_FLAG, cells, count_flagged, fmt, geomean, isnan, mark, median, minmax,
                     number, provenance, read_rows, spread, spread_text, write_atomically)
from .kernel_sets import kernel_sets

KEY = ("model", "system", "backend", "family", "ordering", "ordering_used", "threads", "thread_env")
# The summary reads the minimum over a cell's repetitions: on a shared machine interference only adds time.
FACTOR, SOLVE = "factorize_min_s", "solve_min_s"
# The timings whose repetition spreads estimate the run's noise band.
TIMED = ("factorize_s", "solve_s")
# How the report reads the thesis' "slightly faster": a geometric-mean ratio below this.
SLIGHTLY = 1.5
# The backend that never calls the BLAS: the control of the kernel set comparison.
CONTROL = "dense_llt"
# SPREAD_NOTE (common.py) speaks of medians; the tables here show the least repetition.
SPREAD_NOTE_MIN = (f"{FLAG}: this timing's repetitions are more than {SPREAD_FLAG:g}x apart (largest / least): a "
                   "thread waited on a descheduled worker or the machine was busy. The table shows the least "
                   "repetition, which interference only lengthens, but a ratio built on a flagged timing is less "
                   "certain than the noise band says. A spread is written (least - largest, n = repetitions); from "
                   "three repetitions on it leaves out the first, which warms up.")


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

    def largest_model(self):
        """The tier with the most vertices (unknowns where no vertex count was written), not the last in file
        order."""
        def size(m):
            own = [c for c in self.cells if c.model == m]
            return tuple(max((c.get(k) for c in own if not isnan(c.get(k))), default=-1) for k in ("vertices", "n"))
        return max(self.models, key=size) if self.models else ""


def rep_spread(get, measure):
    """Largest / least repetition of a timing; NaN without two repetitions."""
    lo, hi, n = spread(get, measure)
    return hi / lo if not isnan(n) and n >= 2 and not isnan(hi) and lo > 0 else NAN


class Noise:
    """The run's one noise band, from its own repetition spreads: a ratio of two timings counts as a difference
    only outside 1/band - band. The upper quartile of largest / least over every repeated factorize and solve:
    three quarters of the timings varied less than that between their own repetitions."""

    def __init__(self, cells_):
        v = sorted(x for c in cells_ if c.ok() for m in TIMED for x in [rep_spread(c.get, m)] if not isnan(x))
        self.count, self.median = len(v), median(v)
        self.band = (statistics.quantiles(v, n=4, method="inclusive")[2] if len(v) > 1 else v[0]) if v else 1.0

    def bounds(self):
        return 1 / self.band, self.band

    def range_text(self):
        return f"{1 / self.band:.2f}-{self.band:.2f}"

    def rule(self):
        """How a ratio is judged, for the prose under a table."""
        if not self.count:
            return "a ratio is judged against 1 alone (no noise band: no timing repeated)"
        return f"a ratio counts as a difference only outside the noise band {self.range_text()} (header)"

    def describe(self):
        if not self.count:
            return ("none estimated: no timing repeated (--factor-reps / --solve-reps 1), so ratios are judged "
                    "against 1 alone and small differences may be noise")
        return (f"{self.range_text()}: the upper quartile of largest / least repetition over the {self.count} "
                f"factorize and solve timings that repeated (their median: {self.median:.2f}); a ratio inside it "
                "is not counted as a difference anywhere in this report but the BLAS kernel set comparison, which "
                "judges each cell by its own spreads")


def judge(items):
    """(above, below, within) counts of (ratio, lo, hi) triples with a finite ratio."""
    v = [(r, lo, hi) for r, lo, hi in items if not isnan(r) and r > 0 and math.isfinite(r)]
    above = sum(r > hi for r, _, hi in v)
    below = sum(r < lo for r, lo, _ in v)
    return above, below, len(v) - above - below


def judge_band(v, bounds):
    lo, hi = bounds
    return judge((r, lo, hi) for r in v)


def kind(counts):
    """'none', 'above', 'below', 'within' (every cell so), 'mixed' (both directions) or 'partly-above' /
    'partly-below' (one direction, the rest within)."""
    above, below, within = counts
    n = above + below + within
    if n == 0:
        return "none"
    for name, k in (("above", above), ("below", below), ("within", within)):
        if k == n:
            return name
    return "mixed" if above and below else ("partly-above" if above else "partly-below")


def value(c, m):
    return c.get(m) if c is not None and c.ok() else NAN


def analyze_least(c):
    """The least analyze repetition; the median `analyze_s` in a CSV without `analyze_min_s`."""
    x = value(c, "analyze_min_s")
    return value(c, "analyze_s") if isnan(x) else x


def analyze_note(cs):
    """Says which cells fell back to the median analyze time, "" when none did."""
    n = sum(1 for c in cs if c is not None and c.ok() and isnan(c.get("analyze_min_s"))
            and not isnan(c.get("analyze_s")))
    return f" {n} cell(s) lack `analyze_min_s`: their analyze is the median, `analyze_s`." if n else ""


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


def verdict_word(v, bounds):
    """The verdict on one comparison's per-cell ratios (> 1: Cholesky faster), cell by cell against the noise band:
    "confirmed" only when every cell is beyond it."""
    above, below, within = counts = judge_band(v, bounds)
    k, n, g = kind(counts), above + below + within, geomean(v)
    if k == "none":
        return "not measured"
    if k == "above":
        return ("**confirmed**: Cholesky is slightly faster" if g < SLIGHTLY else
                "**confirmed, and understated**: Cholesky is clearly faster, not just slightly")
    if k == "below":
        return "**refuted**: Cholesky is slower in every cell"
    if k == "within":
        return "**no measurable difference**: every cell within the noise band"
    if k == "mixed":
        return (f"**mixed**: Cholesky faster in {above}, slower in {below}"
                + (f", within the noise band in {within}" if within else "") + f" of {n} cells")
    side, count = ("faster", above) if k == "partly-above" else ("slower", below)
    return f"**not in every cell**: Cholesky {side} in {count} of {n} cells, within the noise band in the rest"


def claim_sentence(rows, bounds):
    """Whether Cholesky was faster beyond the noise band in every cell of every comparison listed."""
    kinds = [(name, kind(judge_band(v, bounds))) for name, _, v in rows]
    measured = [(name, k) for name, k in kinds if k != "none"]
    if not measured:
        return "Not measured (no Cholesky / LU or Bunch-Kaufman pair ran). "
    failing = [name for name, k in measured if k != "above"]
    s = ("The claim holds in every cell measured: Cholesky factorized faster beyond the noise band in every "
         "measured comparison above. " if not failing else
         f"The claim does not hold in every cell measured: not so for {'; '.join(failing)} (see the verdicts). ")
    unmeasured = [name for name, k in kinds if k == "none"]
    return s + (f"Not measured: {'; '.join(unmeasured)}. " if unmeasured else "")


def lu_sentence(g_lu, lu, g_any, any_, bounds):
    """The LU gap, and whether LU's doubled flop count shows in it."""
    parts = [text for g, text in ((g_lu, f"dense LU took {fmt(g_lu, '{:.2f}')}x the time of dense Cholesky"),
                                  (g_any, f"the fastest sparse LU {fmt(g_any, '{:.2f}')}x the fastest sparse "
                                          "Cholesky")) if not isnan(g)]
    if not parts:
        return ""
    above, below, within = judge_band(lu + any_, bounds)
    gap = min(g for g in (g_lu, g_any) if not isnan(g))
    flops = "LU does twice the flops (dense: 2n^3/3 against n^3/3) and stores L and U"
    if not below and not within:
        lead = 'Against LU the gap is larger than "slightly"' if gap >= SLIGHTLY else 'Against LU "slightly" fits'
        tail = f", as expected: {flops}. "
    elif below:
        lead, tail = "Against LU", f"; {flops}, yet LU was faster beyond the noise band in {below} of these cells. "
    else:
        lead, tail = "Against LU", f"; {flops}, but that does not show beyond the noise band in every cell. "
    return f"{lead}: {' and '.join(parts)} (geometric means of ratios of least factorize times){tail}"


def bk_sentence(g_bk, bk, bounds):
    """Bunch-Kaufman against Cholesky, phrased from its own verdict."""
    k = kind(judge_band(bk, bounds))
    if k == "none":
        return "Bunch-Kaufman LDL^T was not measured (no dense cell ran)."
    head = (f"Bunch-Kaufman LDL^T does the same n^3/3 flops as Cholesky; it took {g_bk:.2f}x Cholesky's time "
            f"(geometric mean, range {rng(bk)})")
    if k == "above":
        return (head + ", which comes from the symmetric pivot search and the less regular blocking of dsytrf"
                + (', and is where "slightly" fits.' if g_bk < SLIGHTLY else ": clearly slower as well, not slightly."))
    if k == "below":
        return head + ": Bunch-Kaufman was faster than Cholesky in every cell, against the claim."
    if k == "within":
        return head + ": no difference beyond the noise band."
    if k == "partly-above":
        return head + ": slower than Cholesky beyond the noise band in some cells only (see its verdict above)."
    if k == "partly-below":
        return head + ": faster than Cholesky beyond the noise band in some cells, against the claim."
    return head + ": the cells disagree beyond the noise band (see its verdict above)."


def verdict_prose(rows, bounds):
    """One paragraph stating the measured verdict from the per-cell ratios (> 1: Cholesky faster)."""
    (_, g_lu, lu), (_, g_bk, bk) = rows[0], rows[1]
    _, g_any, any_ = rows[-1]
    return ("**Measured verdict.** " + claim_sentence(rows, bounds) + lu_sentence(g_lu, lu, g_any, any_, bounds)
            + bk_sentence(g_bk, bk, bounds))


def header(run, p, noise):
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
           "the medians too, `factorize_s`, `solve_s`, and the largest, `factorize_max_s`, `solve_max_s`), and every "
           "ratio below is of such minimums. One thread (BLAS, OpenMP, assembly) unless `--threads`.",
           f"- Noise band {noise.describe()}.",
           "- Errors: `residual` = ||Kx-b||/||b|| (deformation RHS); `error_exact` = ||x-x_ref||/||x_ref|| for "
           "b = K x_ref (spqr: b = A x_ref) with a seeded random x_ref; `error_vs_cholmod` = deformed positions against "
           "CHOLMOD supernodal (default ordering) of the same system.",
           f"- Machine: {p.get('cpu')}; {p.get('hardware_threads')} threads; {p.get('compiler')}; BLAS {p.get('blas')} "
           f"core {p.get('blas_core')} (OPENBLAS_CORETYPE={'unset' if p.get('blas_coretype_env') in ('', 'auto') else p.get('blas_coretype_env')}), "
           f"{p.get('blas_threads')} BLAS threads; git {p.get('git_sha')}."]
    if isnan(load_med):
        out.append("- Load average: not recorded.\n")
    else:
        out.append(f"- Load average (1 min) before each cell: median {load_med:.1f}, max {load_max:.1f}, on "
                   f"{p.get('hardware_threads')} hardware threads"
                   + (": the machine was shared with other jobs.\n" if load_med > 0.5 * hw else ".\n"))
    return "\n".join(out)


def dense_table(run, lu, bk):
    """Dense factorizations of the same matrix with the same BLAS; appends the LU/LL^T and BK/LL^T ratios."""
    out = ["### Dense factorizations (same matrix, same BLAS)\n\n| tier | system | n | LAPACK dpotrf (LL^T) | Eigen LLT | "
           "LAPACK dsytrf (Bunch-Kaufman LDL^T) | LAPACK dgetrf (LU) | LU / LL^T | BK / LL^T | Eigen LLT / dpotrf |\n"
           "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    any_dense = False
    for m in run.models:
        for sys in run.systems:
            pot, llt, b, u = (run.find(m, sys, x) for x in ("lapack_potrf", CONTROL, "dense_ldlt_bk", "dense_lu"))
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
    out.append("\nTimes: the least factorize repetition. Ratios are quotients of those (> 1: Cholesky faster). Flop "
               "counts: LL^T and LDL^T n^3/3, LU 2n^3/3.\n")
    return "\n".join(out)


def with_ordering(c):
    return f"{fsec(c.get(FACTOR))} ({c.ordering})" if c is not None and c.ok() else "-"


def sparse_table(run, cm_ratio, eig_ratio, any_ratio):
    """Each sparse backend at its default ordering and at its best measured one (an LU code given an ordering meant
    for Cholesky, e.g. AMD for SparseLU, is not a fair opponent); appends the LU/Cholesky ratios of the best."""
    out = ["### Sparse factorizations (same matrix)\n\n`default`: each backend with its own default ordering; `best`: "
           "each backend with the ordering that factorized fastest among those measured (in parentheses). Times: the "
           "least factorize repetition.\n\n| tier | "
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


def verdict(run, noise):
    lu, bk, cm, eig, any_ = [], [], [], [], []
    dense, sparse = dense_table(run, lu, bk), sparse_table(run, cm, eig, any_)
    rows = [("dense LU / dense Cholesky", lu), ("dense Bunch-Kaufman LDL^T / dense Cholesky", bk),
            ("sparse UMFPACK LU / CHOLMOD supernodal LL^T (best orderings)", cm),
            ("sparse Eigen SparseLU / Eigen simplicial LL^T (best orderings)", eig),
            ("fastest sparse LU / fastest sparse Cholesky (any backend, any ordering)", any_)]
    rows = [(name, geomean(v), v) for name, v in rows]
    bounds = noise.bounds()
    out = ["## Verdict on the thesis' claim (section 2.2.3: Cholesky is slightly faster than LU and Bunch-Kaufman)\n",
           "| comparison | ratio of least factorize times (geometric mean over cells) | range over cells | cells: "
           "Cholesky faster / slower / within noise | verdict |\n|---|---:|---:|---:|---|"]
    out += [f"| {name} | {fmt(g, '{:.2f}')} | {rng(v)} | {'{} / {} / {}'.format(*judge_band(v, bounds))} | "
            f"{verdict_word(v, bounds)} |" for name, g, v in rows]
    out += ["", f"A cell is (tier, system); {noise.rule()}, and \"confirmed\" needs every cell beyond it. "
            f"\"Slightly\": a geometric mean below {SLIGHTLY:g}x.", "", verdict_prose(rows, bounds), "",
            "Dense Cholesky is LAPACK dpotrf where it ran (same library as dgetrf / dsytrf), else Eigen's LLT. The "
            "thesis measured on an AMD64 3000+ (2008) without saying which implementations it compared.\n",
            dense, sparse]
    return "\n".join(out)


def ls_time(c):
    """Least analyze + factorize + one solve (QR's analysis is part of its factorize)."""
    return analyze_least(c) + value(c, FACTOR) + value(c, SOLVE)


def least_squares(run, noise):
    """QR of A (spqr) against Cholesky of A^T A (the reference): accuracy on the same systems, time, memory."""
    out = ["## Least squares on A (SPQR) against the normal equations\n\n`spqr` factors the naive build's A itself "
           "(QR; A^T A is never formed, so the condition number is not squared); the reference is CHOLMOD supernodal on "
           "K = A^T A. `error_exact`: ||x - x_ref|| / ||x_ref|| for a right-hand side with a known solution; time: "
           "analyze + factorize + one solve, each its least repetition (QR's analysis is part of its factorize); "
           "memory: the factor and the cell's peak RSS."
           "\n\n| tier | system | n | error_exact QR / Cholesky | vs CHOLMOD | residual QR / Cholesky | analyze + "
           "factorize + solve QR / Cholesky | factor MiB QR / Cholesky | peak RSS MiB QR / Cholesky | status |\n"
           "|---|---|---:|---:|---:|---:|---:|---:|---:|---|"]
    shown = []
    for m in run.models:
        for sys in run.systems:
            q, c = run.find(m, sys, "spqr"), run.find(m, sys, "cholmod_supernodal")
            if q is None:
                continue
            shown += [q, c]
            pair = lambda a, b, f: f"{f(a)} / {f(b)}"  # noqa: E731
            e = lambda x: fmt(x, "{:.1e}")  # noqa: E731
            mib = lambda x: fmt(x / MIB, "{:.1f}")  # noqa: E731
            out.append(f"| {m} | {sys} | {fmt(value(q, 'n'), '{:.0f}')} | "
                       f"{pair(value(q, 'error_exact'), value(c, 'error_exact'), e)} | {e(value(q, 'error_vs_cholmod'))} | "
                       f"{pair(value(q, 'residual'), value(c, 'residual'), e)} | {pair(ls_time(q), ls_time(c), fsec)} | "
                       f"{pair(value(q, 'factor_bytes'), value(c, 'factor_bytes'), mib)} | "
                       f"{pair(value(q, 'peak_rss_bytes'), value(c, 'peak_rss_bytes'), mib)} | "
                       f"{'ok' if q.ok() else q.message} |")
    if not shown:
        return ""
    return "\n".join(out) + "\n" + analyze_note(shown) + "\n\n" + least_squares_verdict(run, noise) + "\n"


# Cholesky's error more than this many times QR's counts as digits the normal equations lose.
DIGIT = 10.0


def div(a, b):
    """a / b, NaN unless both are finite and b positive."""
    return a / b if not isnan(a) and not isnan(b) and b > 0 and math.isfinite(a) and math.isfinite(b) else NAN


def ls_ratios(run, sys):
    """Per tier where both ran: Cholesky's error / QR's, then QR / Cholesky for time, peak RSS and solve."""
    out = []
    for m in run.models:
        q, c = run.find(m, sys, "spqr"), run.find(m, sys, "cholmod_supernodal")
        if q is None or c is None or not q.ok() or not c.ok():
            continue
        out.append((div(c.get("error_exact"), q.get("error_exact")), div(ls_time(q), ls_time(c)),
                    div(q.get("peak_rss_bytes"), c.get("peak_rss_bytes")), div(q.get(SOLVE), c.get(SOLVE))))
    return [list(x) for x in zip(*out)] if out else []


def cost_word(v, bounds, noun):
    """"more time", "less time", ... from per-cell ratios QR / Cholesky against `bounds`."""
    above, below, within = counts = judge_band(v, bounds)
    k = kind(counts)
    if k in ("above", "below"):
        return f"{'more' if k == 'above' else 'less'} {noun} in every cell"
    if k == "within":
        return f"as much {noun} within the noise band"
    parts = [(w, n) for w, n in (("more", above), ("less", below), ("as much within noise", within)) if n]
    text = [f"{w} {noun} in {n}" if i == 0 else f"{w} in {n}" for i, (w, n) in enumerate(parts)]
    return f"{', '.join(text)} of {above + below + within} cells"


def ls_digits(lossy, kept):
    """Which systems lose digits to the normal equations (Cholesky's error more than DIGIT x QR's in every tier)."""
    s = ""
    if lossy:
        s += (f"On {', '.join(lossy)} Cholesky's error is more than {DIGIT:g}x QR's in every tier: the normal "
              "equations square the condition number and lose digits QR keeps, so `vs CHOLMOD` above is mostly "
              "Cholesky's own error there. ")
    if kept:
        s += f"On {', '.join(kept)} Cholesky's error is at most {DIGIT:g}x QR's in at least one tier. "
    return s


def ls_cost(time, rss, solve, noise):
    """What QR costs against Cholesky over every cell: time and solve against the noise band, memory against 1."""
    band = noise.bounds()
    return (f"Over every tier and system QR costs {cost_word(time, band, 'time')}, "
            f"{cost_word(rss, (1.0, 1.0), 'peak memory')} and, per frame, {cost_word(solve, band, 'solve time')}"
            + (" (its solve applies Q^T to the stacked right-hand side)." if kind(judge_band(solve, band)) == "above"
               else "."))


def least_squares_verdict(run, noise):
    """The ratios QR / Cholesky over the systems where both ran (geometric means, per system), then what they say
    over all of them."""
    lines, lossy, kept, total = [], [], [], [[], [], [], []]
    for sys in run.systems:
        r = ls_ratios(run, sys)
        if not r:
            continue
        err, time, rss, solve = r
        for acc, x in zip(total, r):
            acc += x
        digits = kind(judge_band(err, (0.0, DIGIT)))
        if digits != "none":
            (lossy if digits == "above" else kept).append(sys)
        lines.append(f"{sys}: Cholesky's error is {fmt(geomean(err), '{:.3g}')}x QR's (range {rng(err)}); QR took "
                     f"{fmt(geomean(time), '{:.2f}')}x Cholesky's time (least analyze + factorize + solve; range "
                     f"{rng(time)}), {fmt(geomean(rss), '{:.2f}')}x its peak memory (range {rng(rss)}) and "
                     f"{fmt(geomean(solve), '{:.2f}')}x its least solve time (range {rng(solve)})")
    if not lines:
        return ""
    return ("**Measured** (geometric means over tiers). " + "; ".join(lines) + ". " + ls_digits(lossy, kept)
            + ls_cost(*total[1:], noise))


def every_backend(run):
    out = ["## Every backend, default ordering\n\n| tier | system | n | backend | ordering used | analyze | factorize | "
           "solve | nnz(L) | GFlop/s | factor MiB | peak RSS MiB | residual | error_exact | vs CHOLMOD | status |\n"
           "|---|---|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
    shown = []
    for m in run.models:
        for sys in run.systems:
            for be in run.backends:
                r = run.find(m, sys, be)
                if r is None:
                    continue
                shown.append(r)
                v = lambda k: value(r, k)  # noqa: E731
                sp = lambda k: spread_text(r.get, k, fsec) if r.ok() else ""  # noqa: E731
                out.append(f"| {m} | {sys} | {fmt(r.get('n'), '{:.0f}')} | {be} | {r.ordering_used or '-'} | "
                           f"{fsec(analyze_least(r))} | {fsec(v(FACTOR))} {sp('factorize_s')} | "
                           f"{fsec(v(SOLVE))} {sp('solve_s')} | "
                           f"{fmt(v('nnz_factor'), '{:.0f}')} | {fmt(v('gflops'), '{:.2f}')} | "
                           f"{fmt(v('factor_bytes') / MIB, '{:.1f}')} | {fmt(v('peak_rss_bytes') / MIB, '{:.0f}')} | "
                           f"{fmt(v('residual'), '{:.1e}')} | {fmt(v('error_exact'), '{:.1e}')} | "
                           f"{fmt(v('error_vs_cholmod'), '{:.1e}')} | {'ok' if r.ok() else r.message} |")
    ok = [c.get for c in run.cells if c.ok() and c.ordering == "default"]
    return ("\n".join(out) + "\n\nanalyze, factorize, solve: the least repetition; factorize and solve with their "
            f"spread (least - largest, n = repetitions).{analyze_note(shown)}\n\n{SPREAD_NOTE_MIN} Flagged here: "
            f"{count_flagged(ok, ['factorize_s', 'solve_s'])} timing(s).\n")


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
    big = run.largest_model()
    out = [f"## Orderings (sparse direct backends, largest tier: {big})\n\n| system | backend | ordering | "
           "ordering used | analyze | factorize | solve | nnz(L) | status |\n|---|---|---|---|---:|---:|---:|---:|---|"]
    shown = []
    for sys in run.systems:
        for r in run.cells:
            if r.model == big and r.system == sys and r.family in ("sparse-cholesky", "sparse-lu"):
                shown.append(r)
                out.append(f"| {sys} | {r.backend} | {r.ordering} | {r.ordering_used or '-'} | "
                           f"{fsec(analyze_least(r))} | {fsec(value(r, FACTOR))}{mark(r.get, 'factorize_s')} | "
                           f"{fsec(value(r, SOLVE))}{mark(r.get, 'solve_s')} | "
                           f"{fmt(value(r, 'nnz_factor'), '{:.0f}')} | {'ok' if r.ok() else r.message} |")
    return ("\n".join(out) + "\n\nThe largest tier: the one with the most vertices. analyze, factorize, solve: the "
            f"least repetition; {FLAG}: repetitions more than {SPREAD_FLAG:g}x apart (see Every backend)."
            f"{analyze_note(shown)}\n")


def accuracy(c):
    """The distance from the refined (exact to its tolerance) solution where measured, else error_exact."""
    e = value(c, "error_vs_refined")
    return (fmt(e, "{:.1e}") + " (vs refined)") if not isnan(e) else (fmt(value(c, "error_exact"), "{:.1e}") + " (exact)")


def fastest(run):
    """Best (backend, ordering) per system and tier for the interactive split (factorize once, solve per frame),
    with what it costs in memory and what it gives in accuracy; then the fastest factorize and solve, and the
    smallest peak RSS."""
    at = f" at {run.counts[0]:.0f} thread(s)" if run.counts else ""
    out = [f"## Fastest choice per tier and system{at}\n\n| tier | system | fastest analyze + factorize + 20 solves "
           "(backend/ordering) | time | peak RSS MiB | factor MiB | error | fastest factorize | time | fastest solve "
           "| time | least peak RSS | MiB |\n|---|---|---|---:|---:|---:|---|---|---:|---|---:|---|---:|"]
    shown = []
    name = lambda c: f"{c.backend}/{c.ordering}" if c is not None else "-"  # noqa: E731
    mib = lambda c, k: fmt(value(c, k) / MIB, "{:.1f}") if c is not None else "-"  # noqa: E731
    for m in run.models:
        for sys in run.systems:
            ok = [c for c in run.cells if c.model == m and c.system == sys and c.ok()]
            if not ok:
                continue
            shown += ok
            total = lambda c: analyze_least(c) + c.get(FACTOR) + 20 * c.get(SOLVE)  # noqa: E731
            pick = lambda cs, f: min(cs, key=f) if cs else None  # noqa: E731
            bf = pick([c for c in ok if c.family != "iterative"], lambda c: c.get(FACTOR))
            bs, bt, bm = pick(ok, lambda c: c.get(SOLVE)), pick(ok, total), pick(ok, lambda c: c.get("peak_rss_bytes"))
            out.append(f"| {m} | {sys} | {name(bt)} | {fsec(total(bt))} | {mib(bt, 'peak_rss_bytes')} | "
                       f"{mib(bt, 'factor_bytes')} | {accuracy(bt)} | {name(bf)} | "
                       f"{fsec(bf.get(FACTOR)) if bf else '-'} | {name(bs)} | {fsec(bs.get(SOLVE))} | {name(bm)} | "
                       f"{mib(bm, 'peak_rss_bytes')} |")
    out.append("\nTimes: each phase's least repetition (analyze + factorize + 20 x solve for the first)."
               f"{analyze_note(shown)} "
               "error: the largest coordinate difference from the multifrontal_refined cell's solution (bounding-box "
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



def cell_bounds(get0, get1, noise, scatter):
    """Where a control-corrected ratio variant / this run lies beyond both runs' spreads of one cell: below
    1 / (variant's largest / least) the variant's slowest repetition beats this run's fastest; above (this run's
    largest / least) its fastest loses to this run's slowest. A side without repetitions takes the noise band; both
    widen by `scatter`, how far the control cells lie from their own mean (the correction's uncertainty)."""
    s0, s1 = rep_spread(get0, "factorize_s"), rep_spread(get1, "factorize_s")
    return 1 / ((noise.band if isnan(s1) else s1) * scatter), (noise.band if isnan(s0) else s0) * scatter


def blas_verdict(core, counts):
    """The kernel set verdict from (slower, faster, within) counts of the BLAS-calling cells."""
    slower, faster, within = counts
    n, k = slower + faster + within, kind(counts)
    if k == "none":
        return "not measured"
    if k == "within":
        return "no measurable difference: every BLAS-calling cell lies within both runs' spreads"
    if k in ("above", "below"):
        side = "slower" if k == "above" else "faster"
        return f"{core} is {side} in every BLAS-calling cell, beyond both runs' spreads"
    if k != "mixed":
        side, count = ("slower", slower) if k == "partly-above" else ("faster", faster)
        return (f"{core} is {side} beyond both runs' spreads in {count} of the {n} BLAS-calling cells, and within them "
                "in the rest")
    return (f"no uniform effect: {core} faster in {faster}, slower in {slower} and within both runs' spreads in "
            f"{within} of the {n} BLAS-calling cells")


def family_text(judged, family):
    """A family's backends (as measured) with the geometric mean and range of their corrected ratios."""
    v = [r for c, r, _, _ in judged if (c.family == "dense") == (family == "dense")]
    names = sorted({c.backend for c, _, _, _ in judged if (c.family == "dense") == (family == "dense")})
    return f"{family} ({', '.join(names)}) {fmt(geomean(v), '{:.2f}')} (range {rng(v)})" if v else ""


def variant_section(run, path, noise):
    """One BLAS kernel set run (solvers_blas_*.csv) against this run: factorize and solve ratios. Eigen's dense LLT
    never calls the BLAS: its ratio is the variant run's drift apart from the BLAS, which every other ratio is
    divided by; each cell is then judged by its own repetition spreads in both CSVs."""
    rows = read_rows(path)
    p = provenance(rows)
    vals = {(r["model"], r["system"], r["backend"], r["ordering"], r["measure"]): number(r["value"])
            for r in rows if r["status"] == "ok" and r["value"] != ""}
    pairs = [(r, lambda m, k=(r.model, r.system, r.backend, r.ordering): vals.get(k + (m,), NAN)) for r in run.cells
             if r.ordering == "default" and r.ok() and (r.model, r.system, r.backend, r.ordering, FACTOR) in vals]
    ctrl = [g(FACTOR) / r.get(FACTOR) for r, g in pairs if r.backend == CONTROL]
    drift = geomean(ctrl)
    scale = 1.0 if isnan(drift) else drift
    scatter = max((max(x / scale, scale / x) for x in ctrl), default=1.0)
    out = [f"### {p.get('blas')} core {p.get('blas_core')} (OPENBLAS_CORETYPE={p.get('blas_coretype_env')}), "
           f"`{os.path.basename(path)}`\n\n| tier | system | backend | factorize here | factorize variant | ratio | "
           "ratio / control | beyond both spreads | solve here | solve variant | solve ratio |\n"
           "|---|---|---|---:|---:|---:|---:|---|---:|---:|---:|"]
    judged = []  # (cell, corrected ratio, lo, hi) of the BLAS-calling cells
    for r, g in pairs:
        f0, f1 = r.get(FACTOR), g(FACTOR)
        corr = f1 / f0 / scale
        word = "control"
        if r.backend != CONTROL:
            lo, hi = cell_bounds(r.get, g, noise, scatter)
            judged.append((r, corr, lo, hi))
            word = "slower" if corr > hi else ("faster" if corr < lo else "within")
        out.append(f"| {r.model} | {r.system} | {r.backend} | {fsec(f0)} {spread_text(r.get, 'factorize_s', fsec)} | "
                   f"{fsec(f1)} {spread_text(g, 'factorize_s', fsec)} | {fratio(f1, f0)} | {fmt(corr, '{:.2f}')} | "
                   f"{word} | {fsec(r.get(SOLVE))} | {fsec(g(SOLVE))} | {fratio(g(SOLVE), r.get(SOLVE))} |")
    tiers = [m for m in run.models if any(r.model == m and r.backend == CONTROL for r, _ in pairs)]
    return "\n".join(out) + "\n\n" + variant_summary(p.get("blas_core"), ctrl, (drift, scatter, tiers), judged, noise)


def control_text(ctrl, drift, scatter, tiers, judged):
    """What the control measured and how the ratios use it."""
    if not ctrl:
        return "No control cell (dense_llt) ran in both: the ratios are not corrected for the variant run's drift."
    others = [m for m in dict.fromkeys(c.model for c, _, _, _ in judged) if m not in tiers]
    return (f"Eigen LLT control (no BLAS): {drift:.2f} (geometric mean, range {rng(ctrl)}), the variant run's speed "
            "apart from the BLAS: every BLAS-calling ratio is divided by it (`ratio / control`), and each cell's "
            f"bounds widen by x{scatter:.2f}, the control cells' scatter about that mean."
            + (f" The control ran on {', '.join(tiers)} only: on {', '.join(others)} the correction assumes the same "
               "drift." if others else ""))


def variant_summary(core, ctrl, control, judged, noise):
    """The control, the corrected geometric mean, the verdict and the per-family means of one variant."""
    corr = [r for _, r, _, _ in judged]
    control = control_text(ctrl, *control, judged)
    families = "; ".join(x for x in (family_text(judged, "dense"), family_text(judged, "sparse")) if x)
    counts = judge((r, lo, hi) for _, r, lo, hi in judged)
    return (f"{control} {'Corrected f' if ctrl else 'F'}actorize ratio, geometric mean over the BLAS-calling cells: "
            f"**{fmt(geomean(corr), '{:.2f}')}** (range {rng(corr)}). A cell counts as a difference only beyond both "
            "runs' factorize spreads (least - largest, in parentheses); a side without repetitions "
            + (f"takes the run's noise band, {noise.range_text()}" if noise.count else
               "has no spread (nor a noise band)")
            + f". Verdict: {blas_verdict(core, counts)}.\n\n"
            + (f"By family{' (corrected)' if ctrl else ''}: {families}.\n" if families else ""))


def blas(run, p, results, noise):
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
                "call the BLAS (each table lists those the variant ran) plus Eigen's own dense LLT as a control (it "
                "never calls the BLAS, so its ratio shows how much faster or slower the variant run was for other "
                "reasons). Ratio = variant time / this run's time, of the least factorize and solve repetitions (< 1: "
                f"the variant is faster).{same}\n")
    return "\n".join(out + [variant_section(run, path, noise) for _, _, path in distinct[1:]])


def write(results):
    """Writes RESULTS/solvers.md; False when there is no solvers.csv."""
    rows = read_rows(os.path.join(results, "solvers.csv"))
    if not rows:
        return False
    run, p = Run(rows), provenance(rows)
    noise = Noise(run.cells)
    parts = [header(run, p, noise), fastest(run), verdict(run, noise), least_squares(run, noise), every_backend(run),
             mixed_precision(run), orderings(run), threads(run), blas(run, p, results, noise)]
    write_atomically(os.path.join(results, "solvers.md"), "\n".join(x for x in parts if x))
    return True
