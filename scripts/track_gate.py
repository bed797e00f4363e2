#!/usr/bin/python3
"""The regression gate of the tracking suite: compares a history file (experiments/track.cpp) with a baseline's.

  track_gate.py BASELINE.csv NOW.csv [--threshold PCT] [--alpha P] [--min-delta-ms MS] [--markdown FILE]
                [--cell GLOB] [--measure M]

By measure class (the `class` column the driver writes):
  deterministic  nnz(L), flops, factor / matrix bytes, predicted bytes, n, nnz, iterations: compared exactly;
                 any change is reported, an increase over --det-threshold (0.5%) fails
  memory         peak RSS (the child's VmHWM): the median over repeats fails above --rss-threshold (5%)
  cpu            CPU time of a phase (init, frame; build, analyze, factorize, solve), the cells running
                 single-threaded: time-slicing by other processes does not lengthen it, so it is compared as it
                 is; fails only when the median is more than --threshold (15%) slower AND a one-sided
                 Mann-Whitney U test (scipy, exact for small samples without ties) on the runs normalized by
                 their round's drift gives p < --alpha (0.01) AND the normalized median is also more than
                 --threshold slower AND the slowdown (the smaller of the raw and normalized medians' increase)
                 is at least --min-delta-ms (3 ms): a slowdown past the threshold and significant but smaller
                 than that floor is "recorded only" (named in the report, not failed). alpha is 0.01, not 0.05:
                 the gate makes about 50 CPU-time comparisons a run, and at a per-run spread of 15-20% (this
                 box at load 1-3) 0.05 raised 14 false alarms in the 20 ordered pairs of five runs of one commit,
                 0.01 none (scripts/track_gate_power.py measures it on any such runs); the floor:
                 between runs of one commit, phases under 10 ms moved by up to 2.6 ms (results/history/README.md).
                 A round's drift: the median ratio of all the CPU times of that round to
                 their baseline medians, when >= --drift-cells (10) are compared (contention for caches and
                 memory with other processes moves every cell of a round; one cell's regression does not move
                 the median);
                 needs >= --min-repeats (5) runs on each side; baseline medians under --min-time-s (5 ms) are
                 reported, not gated
  time           wall time of the same phases, each run normalized by the machine rates measured just before and
                 after it (its `rate`: the memory read rate for builds, analyses and solves, the BLAS dgemm rate
                 for factorizations, both for init = build + analyze + factorize), scaled to the baseline cell's
                 median rates: reported; gated only with --gate-wall (for a quiet machine), by the cpu rule plus
                 the raw (unnormalized) median also more than --threshold slower (normalization may excuse a slow
                 window, never make a failure). On a shared machine wall time moves with the load by up to 5x
                 between runs minutes apart, and the rate probes do not follow it
  info           the whole child's wall and CPU time: recorded, never compared
A cell that failed in NOW fails the gate. Across machines (different machine_id) only deterministic measures are
gated. Prints the comparisons that are not plain "ok" (all of them with --all) and writes the full report as
Markdown with --markdown. Exit: 0 pass, 1 regression (or usage), 2 unreadable history.
Run with Debian's /usr/bin/python3 (python3-scipy).
"""
import argparse
import csv
import fnmatch
import math
import statistics
import sys
from dataclasses import dataclass, field

REQUIRED = ("commit", "date", "machine_id", "cell", "measure", "class", "rate", "value", "repeat",
            "blas_dgemm_before", "blas_dgemm_after", "memory_read_before", "memory_read_after")


class InputError(Exception):
    pass


def _num(text):
    try:
        return float(text) if text not in ("", None) else math.nan
    except ValueError:
        return math.nan


@dataclass
class History:
    """One run of the suite: its metadata and its rows, keyed for the gate."""
    path: str
    meta: dict
    values: dict = field(default_factory=dict)   # (cell, measure) -> {repeat: value}
    classes: dict = field(default_factory=dict)  # (cell, measure) -> (class, rate)
    rates: dict = field(default_factory=dict)    # (cell, repeat) -> {"dgemm": GFlop/s, "read": GB/s}
    failed: dict = field(default_factory=dict)   # cell -> message

    @staticmethod
    def from_rows(rows, path="<rows>"):
        if not rows:
            raise InputError(f"{path}: no rows")
        missing = [c for c in REQUIRED if c not in rows[0]]
        if missing:
            raise InputError(f"{path}: not a tracking history (no column {', '.join(missing)})")
        first = rows[0]
        h = History(path, {k: first.get(k, "") for k in ("commit", "date", "machine_id", "git_sha", "overrides",
                                                         "machine_cpu", "machine_cores", "machine_ram_gib",
                                                         "machine_blas_core", "machine_threads")})
        for r in rows:
            h._add(r)
        return h

    def _add(self, r):
        cell, measure = r["cell"], r["measure"]
        if r["class"] == "status":
            self.failed[cell] = r.get("message", "failed")
            return
        try:
            repeat = int(r["repeat"])
        except ValueError:
            raise InputError(f"{self.path}: {cell} {measure}: repeat '{r['repeat']}' is not a number")
        self.values.setdefault((cell, measure), {})[repeat] = _num(r["value"])
        self.classes[(cell, measure)] = (r["class"], r["rate"])
        dgemm = (_num(r["blas_dgemm_before"]) + _num(r["blas_dgemm_after"])) / 2
        read = (_num(r["memory_read_before"]) + _num(r["memory_read_after"])) / 2
        self.rates[(cell, repeat)] = {"dgemm": dgemm, "read": read}

    @property
    def dirty(self):
        return self.meta.get("git_sha", "").endswith("+dirty")


def load_history(path):
    try:
        with open(path, newline="") as f:
            return History.from_rows(list(csv.DictReader(f)), path)
    except OSError as e:
        raise InputError(f"{path}: {e.strerror}")


@dataclass
class Comparison:
    cell: str
    measure: str
    cls: str
    base: float = math.nan
    now: float = math.nan
    ratio: float = math.nan
    p: float = math.nan
    verdict: str = "ok"  # ok | FAIL | recorded only | changed | new | missing | not gated
    note: str = ""


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
        factors = self.base if side == "base" else self.now
        return [v / factors.get(r, 1.0) for r, v in sorted(h.values[key].items()) if not math.isnan(v)]


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


def _compare_cpu(c, base, now, key, s, same_machine, drift):
    b, n = _runs(base, key), _runs(now, key)
    c.base, c.now = statistics.median(b), statistics.median(n)
    c.ratio = c.now / c.base if c.base > 0 else math.nan
    nb, nn = drift.normalized(base, key, "base"), drift.normalized(now, key, "now")
    norm = statistics.median(nn) / statistics.median(nb) if statistics.median(nb) > 0 else math.nan
    c.note = f"normalized {norm:.3f}"
    # The U test on the runs normalized round by round; both the raw and the normalized medians must be more than
    # the threshold slower: normalization may excuse a slowdown the whole round shared, never make a failure.
    if _time_verdict(c, nb, nn, c.base, s, same_machine):
        if norm > 1 + s.threshold:
            _floor_verdict(c, c.base * (min(c.ratio, norm) - 1), s)
        else:
            c.note += ": within the threshold once normalized by the round's drift, not failed"


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


def compare(base, now, s=Settings()):
    """Every (cell, measure) of either history, compared by its class."""
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
            out.append(Comparison(key[0], key[1], base.classes[key][0], verdict="missing",
                                  note="in the baseline, not in this run"))
    return out


# ------------------------------------------------------------------------------------------------ report
def fmt_value(x, measure):
    if math.isnan(x):
        return ""
    if measure.endswith("_s"):
        return f"{x:.4g}"
    return f"{x:.0f}" if abs(x) < 1e15 else f"{x:.6g}"


def fmt_row(c):
    ratio = "" if math.isnan(c.ratio) else f"{c.ratio:.3f}"
    p = "" if math.isnan(c.p) else f"{c.p:.3g}"
    return [c.cell, c.measure, c.cls, fmt_value(c.base, c.measure), fmt_value(c.now, c.measure), ratio, p,
            c.verdict, c.note]


HEADER = ["cell", "measure", "class", "baseline", "now", "ratio", "p", "verdict", "note"]


def describe(h):
    m = h.meta
    extra = f", overrides: {m['overrides']}" if m.get("overrides") else ""
    return f"{m.get('git_sha') or m['commit'][:12]} ({m['date']}, machine {m['machine_id']}{extra}) {h.path}"


def largest_time_ratios(cmps, cls="cpu", k=5, min_time_s=0.005):
    """The comparisons of a timed class with the largest change either way (those compared: same machine,
    enough runs, over min_time_s)."""
    t = [c for c in cmps if c.cls == cls and not math.isnan(c.ratio) and c.verdict != "new" and
         (not math.isnan(c.p) or cls == "time" and c.base >= min_time_s and c.note.startswith("raw"))]
    return sorted(t, key=lambda c: -abs(math.log(c.ratio)) if c.ratio > 0 else 0)[:k]


def summary_lines(base, now, cmps, s):
    drift = cpu_drift(base, now, s)
    fails = [c for c in cmps if c.verdict == "FAIL"]
    counts = {}
    for c in cmps:
        counts[c.verdict] = counts.get(c.verdict, 0) + 1
    lines = [f"baseline: {describe(base)}", f"now:      {describe(now)}",
             f"rules: deterministic +{s.det_threshold:.1%} | peak RSS +{s.rss_threshold:.0%} | CPU time "
             f"+{s.threshold:.0%}, U-test p < {s.alpha:g} (>= {s.min_repeats} runs), at least "
             f"{s.min_delta_s * 1e3:g} ms slower (else recorded only) | wall time "
             + ("the same, normalized by the machine rates, raw too" if s.gate_wall else "reported (--gate-wall)"),
             "comparisons: " + ", ".join(f"{v} {n}" for v, n in sorted(counts.items())),
             "CPU drift by round (median ratio of the round's CPU times to the baseline's medians), baseline / now: "
             + " / ".join(" ".join(f"{f:.3f}" for _, f in sorted(d.items())) or "none"
                          for d in (drift.base, drift.now))]
    recorded = [c for c in cmps if c.verdict == "recorded only"]
    if recorded:
        lines.append(f"recorded only (past the threshold and significant, but under the {s.min_delta_s * 1e3:g} ms "
                     "floor: this box's CPU time of one commit moves that much between runs): "
                     + ", ".join(f"{c.cell} {c.measure} {c.ratio:.3f} (+{(c.now - c.base) * 1e3:.1f} ms)"
                                 for c in recorded))
    for cls, what in (("cpu", "CPU time"), ("time", "normalized wall time")):
        big = largest_time_ratios(cmps, cls, min_time_s=s.min_time_s)
        if big:
            lines.append(f"largest {what} changes: " + ", ".join(f"{c.cell} {c.measure} {c.ratio:.3f}" for c in big))
    lines.append(f"verdict: {'FAIL (' + str(len(fails)) + ' regression(s))' if fails else 'pass'}")
    return lines


def print_report(base, now, cmps, s, show_all):
    rows = [fmt_row(c) for c in cmps if show_all or c.verdict not in ("ok", "not gated")]
    if rows:
        widths = [max(len(str(r[i])) for r in rows + [HEADER]) for i in range(len(HEADER))]
        for r in [HEADER] + rows:
            print("  ".join(str(x).ljust(w) for x, w in zip(r, widths)).rstrip())
        print()
    for line in summary_lines(base, now, cmps, s):
        print(line)


def markdown(base, now, cmps, s):
    out = ["# Tracking suite: last comparison", "", "Written by `scripts/track_gate.py` (`./run track`).", ""]
    out += [f"- {line}" for line in summary_lines(base, now, cmps, s)]
    table = ["| " + " | ".join(HEADER) + " |", "|" + "---|" * len(HEADER)]
    for title, pick in (("Failures", lambda c: c.verdict == "FAIL"),
                        ("Recorded only (under the --min-delta-ms floor)", lambda c: c.verdict == "recorded only"),
                        ("Other changes", lambda c: c.verdict in ("changed", "new", "missing")),
                        ("All comparisons", lambda c: True)):
        rows = [c for c in cmps if pick(c)]
        out += ["", f"## {title}", ""]
        out += table + ["| " + " | ".join(fmt_row(c)) + " |" for c in rows] if rows else ["none"]
    return "\n".join(out) + "\n"


def write_atomically(path, text):
    import os
    tmp = f"{path}.tmp.{os.getpid()}"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)


class UsageParser(argparse.ArgumentParser):
    """argparse whose usage errors exit 1, as every command of the project (argparse's own is 2: bad input here)."""

    def error(self, message):
        self.print_usage(sys.stderr)
        print(f"{self.prog}: error: {message}", file=sys.stderr)
        sys.exit(1)


def parse_args(argv):
    ap = UsageParser(prog="track_gate", description=__doc__.split("\n")[0], allow_abbrev=False,
                     formatter_class=argparse.RawDescriptionHelpFormatter, epilog="\n".join(__doc__.split("\n")[2:]))
    ap.add_argument("baseline")
    ap.add_argument("now")
    ap.add_argument("--threshold", type=float, default=15, help="CPU time: allowed slowdown, percent (15)")
    ap.add_argument("--alpha", type=float, default=0.01, help="CPU time: significance level of the U test (0.01)")
    ap.add_argument("--min-delta-ms", type=float, default=3, help="time: a slowdown smaller than this many ms is "
                    "recorded only, never failed (3)")
    ap.add_argument("--det-threshold", type=float, default=0.5, help="deterministic: allowed increase, percent")
    ap.add_argument("--rss-threshold", type=float, default=5, help="peak RSS: allowed increase, percent (5)")
    ap.add_argument("--min-repeats", type=int, default=5, help="time: runs needed on each side (5)")
    ap.add_argument("--min-time-s", type=float, default=0.005, help="time: baseline medians under this are not gated")
    ap.add_argument("--gate-wall", action="store_true", help="gate wall times too (normalized; a quiet machine)")
    ap.add_argument("--drift-cells", type=int, default=10, help="CPU time: measures needed to measure a "
                    "round's drift (10; 0 never normalizes)")
    ap.add_argument("--cell", action="append", default=[], help="only cells matching this glob (repeatable)")
    ap.add_argument("--measure", action="append", default=[], help="only this measure (repeatable)")
    ap.add_argument("--markdown", help="write the report here")
    ap.add_argument("--all", action="store_true", help="print every comparison, not only the notable ones")
    a = ap.parse_args(argv)
    if not (0 < a.alpha < 1) or min(a.threshold, a.det_threshold, a.rss_threshold, a.min_time_s,
                                     a.min_delta_ms) < 0 or a.min_repeats < 1:
        ap.error("thresholds must be >= 0, --alpha in (0, 1), --min-repeats >= 1")
    return a


def main(argv=None):
    a = parse_args(sys.argv[1:] if argv is None else argv)
    s = Settings(a.threshold / 100, a.alpha, a.det_threshold / 100, a.rss_threshold / 100, a.min_repeats,
                 a.min_time_s, tuple(a.cell), tuple(a.measure), a.gate_wall, a.drift_cells, a.min_delta_ms / 1e3)
    try:
        base, now = load_history(a.baseline), load_history(a.now)
    except InputError as e:
        print(f"track_gate: error: {e}", file=sys.stderr)
        return 2
    cmps = compare(base, now, s)
    print_report(base, now, cmps, s, a.all)
    if a.markdown:
        write_atomically(a.markdown, markdown(base, now, cmps, s))
    return 1 if any(c.verdict == "FAIL" for c in cmps) else 0


if __name__ == "__main__":
    sys.exit(main())
