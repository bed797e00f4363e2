"""The regression gate: the one comparator of two records of a suite (a baseline and a run), by measure class.

  python3 -m dbtools.track.gate BASELINE NOW [--threshold PCT] [--alpha P] [--min-delta-ms MS] [--markdown FILE]
                                [--noise-k K] [--target PCT] [--cell GLOB] [--measure M]
                                [--allow-stale] [--allow-foreign]

A record is a history CSV of the tracking suite (experiments/track.cpp) or a bench_phases JSON (gbench.py makes
its rows): the same rules gate both. By measure class (the `class` column):
  deterministic  nnz(L), flops, factor / matrix bytes, predicted bytes, n, nnz, iterations (gbench: n, nnz,
                 nnz_L, bytes): compared exactly; any change is reported, an increase over --det-threshold (0.5%)
                 fails
  memory         peak RSS (the child's VmHWM): the median over repeats fails above --rss-threshold (5%)
  cpu            CPU time of a phase (init, frame; build, analyze, factorize, solve; gbench's cpu_time), the
                 suites running single-threaded: time-slicing by other processes does not lengthen it. Fails only
                 when the median is more than --threshold (15%) slower AND a one-sided Mann-Whitney U test (scipy,
                 exact for small samples without ties) on the runs normalized by their round's drift gives
                 p < --alpha (0.01) AND the normalized median is also more than --threshold slower AND the
                 slowdown (the smaller of the raw and normalized medians' increase) is at least --min-delta-ms
                 (3 ms): a slowdown past the threshold and significant but under that floor is "recorded only"
                 (named, not failed). alpha is 0.01 because a run makes tens of CPU-time comparisons; the floor
                 because short phases of one commit move by milliseconds between runs (power.py measures both on
                 runs of one commit; the record: results/history/README.md). A round's drift: the median ratio
                 of all the CPU times of that round to their baseline medians, when >= --drift-cells (10) are
                 compared (contention with other processes moves every cell of a round; one cell's regression
                 does not move the median). Needs >= --min-repeats (5) runs on each side; baseline medians under
                 --min-time-s (5 ms) are reported, not gated. With several runs a side (pooled), the slowdown
                 must also exceed --noise-k (2) times the phase's run-to-run spread (the larger of the two
                 sides': how far the medians of a side's runs, taken back to back, differ once normalized by the
                 rounds' drift): a phase that moves that much between runs of one commit cannot be gated more
                 finely. Each comparison keeps its resolution (the smallest slowdown the rule can fail there: the
                 threshold, the spread's bar or the floor); the report names the phases whose resolution is
                 coarser than --target (30%: the slowdown the gate is meant to catch), with what sets it
  time           wall time of the same phases, each run normalized by the machine rates measured just before and
                 after it (its `rate`: the memory read rate for builds, analyses and solves, the BLAS dgemm rate
                 for factorizations, both for init = build + analyze + factorize; gbench: no rates, raw),
                 scaled to the baseline cell's median rates: reported; gated only with --gate-wall (a quiet
                 machine), by the cpu rule plus the raw median also more than --threshold slower (normalization
                 may excuse a slow window, never make a failure): on a shared machine wall time follows the load
  info           the whole child's wall and CPU time: recorded, never compared
A cell that failed in NOW fails the gate. A subset run (--only, a --benchmark_filter) compares what ran: a
baseline entry that did not run is "not run", never a failure. Before comparing, the baseline is checked
(provenance.py): a stale one (another suite definition) exits 3, a foreign one (another machine, BLAS core,
thread count or build type) exits 4, each naming the baseline and why; --allow-stale compares anyway,
--allow-foreign gates the deterministic measures only. Prints the comparisons that are not plain "ok" or "not
run" (all of them with --all) and writes the full report as Markdown with --markdown.
Exit: 0 pass, 1 regression (or usage), 2 unreadable record, 3 stale baseline, 4 foreign baseline.
Run with Debian's /usr/bin/python3 (python3-scipy) and PYTHONPATH=<repo>/python.
"""
import argparse
import fnmatch
import math
import statistics
import sys
from dataclasses import dataclass, field

from .history import History, InputError, load_history, run_of  # noqa: F401 (the gate's API: History, load_history)
from .provenance import Refused, check


@dataclass
class Comparison:
    cell: str
    measure: str
    cls: str
    base: float = math.nan
    now: float = math.nan
    ratio: float = math.nan
    p: float = math.nan
    verdict: str = "ok"  # ok | FAIL | recorded only | changed | new | not run | not gated
    note: str = ""
    resolution: float = math.nan  # CPU time: the smallest slowdown (a fraction) the rule could fail here
    bound_by: str = ""  # what sets the resolution: "threshold", "run spread" or "floor"

    def gateable_at(self, slowdown):
        """Whether the rule can fail a slowdown by the fraction `slowdown` of this comparison (CPU time)."""
        return self.resolution < slowdown


@dataclass
class Settings:
    threshold: float = 0.15
    alpha: float = 0.01
    det_threshold: float = 0.005
    rss_threshold: float = 0.05
    min_repeats: int = 5
    min_time_s: float = 0.005
    cells: tuple = ()
    measures: tuple = ()
    gate_wall: bool = False
    drift_cells: int = 10
    min_delta_s: float = 0.003
    noise_k: float = 2.0
    target: float = 0.30


def _ref_rates(h, cell):
    """The baseline cell's median rates: what every normalized time of the cell is scaled to."""
    reps = [r for (c, _), r in h.rates.items() if c == cell]
    return {k: statistics.median([r[k] for r in reps]) if reps else math.nan for k in ("dgemm", "read")}


def normalized(h, cell, measure, rate, ref):
    """The runs of a time measure, each scaled by (its rates / the reference rates); raw when rates are missing."""
    def scaled(m, repeat, kind):
        t = h.values.get((cell, m), {}).get(repeat, math.nan)
        r = h.rates.get((cell, repeat), {}).get(kind, math.nan)
        f = r / ref[kind] if ref[kind] > 0 and r > 0 else 1.0
        return t * f

    out = []
    for repeat, t in sorted(h.values[(cell, measure)].items()):
        if rate == "mixed" and all((cell, m) in h.values for m in ("build_s", "analyze_s", "factorize_s")):
            out.append(scaled("build_s", repeat, "read") + scaled("analyze_s", repeat, "read") +
                       scaled("factorize_s", repeat, "dgemm"))
        else:
            out.append(scaled(measure, repeat, "read" if rate in ("read", "mixed") else "dgemm"))
    return [x for x in out if not math.isnan(x)]


def u_test_greater(now, base):
    """One-sided Mann-Whitney U p-value for 'now tends to be larger than base'."""
    from scipy.stats import mannwhitneyu
    return float(mannwhitneyu(now, base, alternative="greater").pvalue)


def _time_verdict(c, b, n, raw_b, s, same_machine):
    """The rule of the timed classes: not gated across machines, with too few runs or under min_time_s; else FAIL
    when the median is more than the threshold slower and the U test significant."""
    if not same_machine:
        c.verdict, c.note = "not gated", "other machine"
    elif min(len(b), len(n)) < s.min_repeats:
        c.verdict, c.note = "not gated", f"{min(len(b), len(n))} runs < {s.min_repeats}"
    elif raw_b < s.min_time_s:
        c.verdict, c.note = "not gated", f"under {s.min_time_s * 1e3:g} ms"
    else:
        c.p = u_test_greater(n, b)
        return c.ratio > 1 + s.threshold and c.p < s.alpha
    return False


def _floor_verdict(c, slowdown_s, s):
    """A slowdown the rule would fail: FAIL, or "recorded only" when it is under the absolute floor."""
    if slowdown_s >= s.min_delta_s:
        c.verdict = "FAIL"
    else:
        c.verdict = "recorded only"
        c.note += f": {slowdown_s * 1e3:.2f} ms slower, under the {s.min_delta_s * 1e3:g} ms floor (--min-delta-ms)"


def _runs(h, key):
    return [v for v in h.values.get(key, {}).values() if not math.isnan(v)]


@dataclass
class Drift:
    """Per round of each history, the factor by which its CPU times stood above the baseline's medians."""
    base: dict = field(default_factory=dict)  # round -> factor
    now: dict = field(default_factory=dict)

    def normalized(self, h, key, side):
        return list(self.by_round(h, key, side).values())

    def by_round(self, h, key, side):
        """round -> the run of that round divided by the round's drift."""
        factors = self.base if side == "base" else self.now
        return {r: v / factors.get(r, 1.0) for r, v in sorted(h.values[key].items()) if not math.isnan(v)}


def run_spread(rounds):
    """The run-to-run spread of one measure on one side (round -> value; several runs pooled, history.run_of):
    (largest - smallest) / smallest of the medians of its runs' rounds; 0 with one run."""
    by_run = {}
    for r, v in rounds.items():
        by_run.setdefault(run_of(r), []).append(v)
    meds = [statistics.median(v) for v in by_run.values()]
    return (max(meds) - min(meds)) / min(meds) if len(meds) > 1 and min(meds) > 0 else 0.0


def cpu_drift(base, now, s):
    """The load's share of the CPU times, round by round: in round r of a history, the median over every CPU-time
    measure the rule compares (whatever --cell / --measure pick) of (its run in round r / its baseline median);
    1 where fewer than --drift-cells measures ran. The other cells of the same round (a minute or two of the
    run) are the probe of what the load did to CPU time then (caches and memory bandwidth shared with other
    processes): the same kind of work, measured at the same time; one cell's regression does not move the
    median."""
    ref = {}
    for key, (cls, _) in now.classes.items():
        if cls == "cpu" and key in base.values:
            b, n = _runs(base, key), _runs(now, key)
            if min(len(b), len(n)) >= s.min_repeats and statistics.median(b) >= s.min_time_s:
                ref[key] = statistics.median(b)
    return Drift(round_drift(base, ref, s), round_drift(now, ref, s))


def round_drift(h, ref, s):
    """round -> the median over the measures of `ref` ((cell, measure) -> reference time) of h's run in that round
    / the reference; rounds with fewer than s.drift_cells such runs are left out (factor 1)."""
    by_round = {}
    for key, m in ref.items():
        for r, v in h.values.get(key, {}).items():
            if not math.isnan(v):
                by_round.setdefault(r, []).append(v / m)
    return {r: statistics.median(x) for r, x in by_round.items() if s.drift_cells > 0 and len(x) >= s.drift_cells}


def _cpu_bar(c, base, now, key, s, drift):
    """(noise, the slowdown a CPU time must exceed): the runs of a side share a commit, a machine and (taken back to
    back) a load, so how far their medians still differ once normalized by the rounds' drift is the noise a
    slowdown must stand out from: the larger of the two sides' run_spread, times --noise-k, when over the
    threshold. Sets c.resolution: that bar, or the floor's share of the baseline median when larger."""
    noise = max(run_spread(drift.by_round(base, key, "base")), run_spread(drift.by_round(now, key, "now")))
    need = max(s.threshold, s.noise_k * noise)
    floor = s.min_delta_s / c.base if c.base > 0 else math.inf
    c.resolution = max(need, floor)
    c.bound_by = "floor" if floor > need else "run spread" if need > s.threshold else "threshold"
    if base.runs > 1 or now.runs > 1:
        c.note += f", run spread {noise:.1%}"
    return noise, need


def _compare_cpu(c, base, now, key, s, same_machine, drift):
    b, n = _runs(base, key), _runs(now, key)
    c.base, c.now = statistics.median(b), statistics.median(n)
    c.ratio = c.now / c.base if c.base > 0 else math.nan
    nb, nn = drift.normalized(base, key, "base"), drift.normalized(now, key, "now")
    norm = statistics.median(nn) / statistics.median(nb) if statistics.median(nb) > 0 else math.nan
    c.note = f"normalized {norm:.3f}"
    noise, need = _cpu_bar(c, base, now, key, s, drift)
    # The U test on the runs normalized round by round; both the raw and the normalized medians must be more than
    # the threshold slower: normalization may excuse a slowdown the whole round shared, never make a failure.
    if _time_verdict(c, nb, nn, c.base, s, same_machine):
        if norm <= 1 + s.threshold:
            c.note += ": within the threshold once normalized by the round's drift, not failed"
        elif min(c.ratio, norm) <= 1 + need:
            c.note += f": within {s.noise_k:g} x the run-to-run spread ({noise:.1%}), not failed"
        else:
            _floor_verdict(c, c.base * (min(c.ratio, norm) - 1), s)


def _compare_time(c, base, now, key, rate, s, same_machine):
    ref = _ref_rates(base, key[0])
    b, n = normalized(base, *key, rate, ref), normalized(now, *key, rate, ref)
    raw_b, raw_n = (statistics.median(v for v in h.values[key].values() if not math.isnan(v)) for h in (base, now))
    c.base, c.now = statistics.median(b), statistics.median(n)
    c.ratio = c.now / c.base if c.base > 0 else math.nan
    raw = raw_n / raw_b if raw_b > 0 else math.nan
    c.note = f"raw {raw:.3f}" if raw_b > 0 else ""
    if not s.gate_wall:
        c.verdict = "not gated"
        c.note += "; wall time (--gate-wall)"
    elif _time_verdict(c, b, n, raw_b, s, same_machine):
        # The probes around a short cell are noisy under bursty load: a slowdown that only the normalization
        # makes (raw time within the threshold) is reported, not failed.
        if raw > 1 + s.threshold:
            _floor_verdict(c, raw_b * (min(raw, c.ratio) - 1), s)
        else:
            c.note += ": raw time within the threshold, not failed"


def compare_one(base, now, key, s, same_machine, drift=Drift()):
    cls, rate = now.classes[key]
    c = Comparison(key[0], key[1], cls)
    if key not in base.values:
        c.verdict = "new"
        return c
    if cls == "time":
        _compare_time(c, base, now, key, rate, s, same_machine)
        return c
    if cls == "cpu":
        _compare_cpu(c, base, now, key, s, same_machine, drift)
        return c
    c.base = statistics.median(base.values[key].values())
    c.now = statistics.median(now.values[key].values())
    c.ratio = c.now / c.base if c.base else (1.0 if c.now == c.base else math.inf)
    if cls == "deterministic":
        if c.now != c.base:
            c.verdict = "FAIL" if c.ratio > 1 + s.det_threshold else "changed"
    elif cls != "memory":
        c.verdict = "not gated"
    elif not same_machine:
        c.verdict, c.note = "not gated", "other machine"
    elif c.ratio > 1 + s.rss_threshold:
        c.verdict = "FAIL"
    return c


def _wanted(cell, measure, s):
    return ((not s.cells or any(fnmatch.fnmatchcase(cell, g) for g in s.cells)) and
            (not s.measures or measure in s.measures))


def compare(base, now, s=Settings(), same_machine=None):
    """Every (cell, measure) of either history, compared by its class; times only on the same machine (default:
    the same machine id)."""
    if same_machine is None:
        same_machine = base.meta.get("machine_id") == now.meta.get("machine_id")
    drift = cpu_drift(base, now, s)
    out = []
    for cell, message in sorted(now.failed.items()):
        if _wanted(cell, "status", s) or (s.measures and _wanted(cell, s.measures[0], s)):
            out.append(Comparison(cell, "status", "status", verdict="FAIL", note=message))
    for key in sorted(now.values):
        if _wanted(*key, s) and key[0] not in now.failed:
            out.append(compare_one(base, now, key, s, same_machine, drift))
    for key in sorted(set(base.values) - set(now.values)):
        if _wanted(*key, s) and key[0] not in now.failed:
            out.append(Comparison(key[0], key[1], base.classes[key][0], verdict="not run",
                                  note="in the baseline, not in this run"))
    return out


class UsageParser(argparse.ArgumentParser):
    """argparse whose usage errors exit 1, as every command of the project (argparse's own is 2: bad input here)."""

    def error(self, message):
        self.print_usage(sys.stderr)
        print(f"{self.prog}: error: {message}", file=sys.stderr)
        sys.exit(1)


def add_rule_options(ap):
    """The gate's options, the same in every command that gates (gate, the drivers, power)."""
    d = Settings()
    ap.add_argument("--threshold", type=float, default=d.threshold * 100, help="CPU time: allowed slowdown, "
                    "percent (15)")
    ap.add_argument("--alpha", type=float, default=d.alpha, help="CPU time: significance level of the U test (0.01)")
    ap.add_argument("--min-delta-ms", type=float, default=d.min_delta_s * 1e3, help="time: a slowdown smaller than "
                    "this many ms is recorded only, never failed (3)")
    ap.add_argument("--det-threshold", type=float, default=d.det_threshold * 100, help="deterministic: allowed "
                    "increase, percent (0.5)")
    ap.add_argument("--rss-threshold", type=float, default=d.rss_threshold * 100, help="peak RSS: allowed increase, "
                    "percent (5)")
    ap.add_argument("--min-repeats", type=int, default=d.min_repeats, help="time: runs needed on each side (5)")
    ap.add_argument("--min-time-s", type=float, default=d.min_time_s, help="time: baseline medians under this are "
                    "reported, not gated (0.005)")
    ap.add_argument("--gate-wall", action="store_true", help="gate wall times too (normalized; a quiet machine)")
    ap.add_argument("--drift-cells", type=int, default=d.drift_cells, help="CPU time: measures needed to measure a "
                    "round's drift (10; 0 never normalizes)")
    ap.add_argument("--noise-k", type=float, default=d.noise_k, help="CPU time: a slowdown must also exceed this "
                    "many times the phase's run-to-run spread on either side (2; 0: the threshold alone)")
    ap.add_argument("--target", type=float, default=d.target * 100, help="CPU time: the slowdown, percent, the gate "
                    "is meant to catch: the report names the phases whose resolution is coarser (30)")


def add_baseline_options(ap):
    ap.add_argument("--allow-stale", action="store_true", help="compare with a baseline of another suite "
                    "definition (else exit 3)")
    ap.add_argument("--allow-foreign", action="store_true", help="gate the deterministic measures of a baseline "
                    "of another machine or build (else exit 4)")


RULE_OPTIONS = ("threshold", "alpha", "min_delta_ms", "det_threshold", "rss_threshold", "min_repeats", "min_time_s",
                "drift_cells", "noise_k", "target")


def rule_args(a):
    """The command-line arguments that give another command the same rule options as `a`."""
    out = [x for k in RULE_OPTIONS for x in ("--" + k.replace("_", "-"), str(getattr(a, k)))]
    return out + (["--gate-wall"] if a.gate_wall else [])


def add_filter_options(ap):
    ap.add_argument("--cell", action="append", default=[], help="only cells matching this glob (repeatable)")
    ap.add_argument("--measure", action="append", default=[], help="only this measure (repeatable)")


def settings(ap, a, cells=(), measures=()):
    """The Settings of parsed rule options (a usage error through `ap` when out of range)."""
    bad = not (0 < a.alpha < 1) or min(a.threshold, a.det_threshold, a.rss_threshold, a.min_time_s, a.min_delta_ms,
                                        a.drift_cells, a.noise_k) < 0 or a.min_repeats < 1 or a.target <= 0
    if ap and bad:
        ap.error("thresholds, --drift-cells and --noise-k must be >= 0, --alpha in (0, 1), --min-repeats >= 1, "
                 "--target > 0")
    return Settings(a.threshold / 100, a.alpha, a.det_threshold / 100, a.rss_threshold / 100, a.min_repeats,
                    a.min_time_s, tuple(cells), tuple(measures), a.gate_wall, a.drift_cells, a.min_delta_ms / 1e3,
                    a.noise_k, a.target / 100)


def gate(base, now, s, suite_cells=None, allow_stale=False, allow_foreign=False, markdown=None, quiet=False,
         show_all=False, title="Tracking suite", notes=()):
    """The whole gate on two records: the baseline checked (provenance.py), compared, reported (with the lines
    `notes`, e.g. how the baseline was chosen). Exit code."""
    from . import report
    try:
        verdict = check(base, now, suite_cells, allow_stale, allow_foreign)
    except Refused as e:
        print(f"track_gate: error: {e}", file=sys.stderr)
        if markdown:  # the last report must not be an earlier comparison's
            report.write_atomically(markdown, f"# {title}: baseline refused ({e.kind}, exit {e.exit_code})\n\n{e}\n")
        return e.exit_code
    cmps = compare(base, now, s, verdict.same_machine)
    notes = [*notes, *verdict.notes]
    if not quiet:
        report.print_report(base, now, cmps, s, show_all, notes)
    if markdown:
        report.write_atomically(markdown, report.markdown(base, now, cmps, s, notes, title))
    return 1 if any(c.verdict == "FAIL" for c in cmps) else 0


def parse_args(argv):
    ap = UsageParser(prog="python3 -m dbtools.track.gate", description=__doc__.split("\n")[0], allow_abbrev=False,
                     formatter_class=argparse.RawDescriptionHelpFormatter, epilog="\n".join(__doc__.split("\n")[2:]))
    ap.add_argument("baseline")
    ap.add_argument("now")
    add_rule_options(ap)
    add_baseline_options(ap)
    add_filter_options(ap)
    ap.add_argument("--markdown", help="write the report here")
    ap.add_argument("--all", action="store_true", help="print every comparison, not only the notable ones")
    a = ap.parse_args(argv)
    return a, settings(ap, a, a.cell, a.measure)


def main(argv=None):
    a, s = parse_args(sys.argv[1:] if argv is None else argv)
    try:
        base, now = load_history(a.baseline), load_history(a.now)
    except InputError as e:
        print(f"track_gate: error: {e}", file=sys.stderr)
        return 2
    return gate(base, now, s, allow_stale=a.allow_stale, allow_foreign=a.allow_foreign, markdown=a.markdown,
                show_all=a.all)


if __name__ == "__main__":
    sys.exit(main())
