"""The gate's false alarms and power on this machine's own noise: runs of ONE commit (records: history files of
experiments/track.cpp or bench_phases JSONs), gated pair by pair with gate.py's rules.

  python3 -m dbtools.track.power RUN RUN [RUN ...] [--slowdown F] [--pool K] [gate options: --alpha P ...]

false alarms: every ordered pair (A, B) of the runs gated as they are: any FAIL is one (the runs are of one
  commit). --pool K joins K runs into one side (their rounds renumbered), disjoint sets of K against K, to see
  what K times the rounds a side would do (the runs' noise, between runs included).
power: for each such pair and each CPU-time measure the gate tests, that measure of B multiplied by F (--slowdown,
  1.3) and gated again: the share of planted slowdowns that fail, by the phase's baseline median (under / over
  50 ms) and in all.
Exit: 0 (a measurement, not a gate), 1 usage, 2 unreadable history. Run with Debian's /usr/bin/python3.
"""
import copy
import itertools
import statistics
import sys

from . import gate as g


def pooled(hs):
    """One history of the runs `hs`: run k's round r becomes round 1000 k + r."""
    out = copy.deepcopy(hs[0])
    for k, h in enumerate(hs[1:], 1):
        for key, runs in h.values.items():
            out.values.setdefault(key, {}).update({1000 * k + r: v for r, v in runs.items()})
        out.rates.update({(c, 1000 * k + r): v for (c, r), v in h.rates.items()})
    return out


def sides(hs, pool):
    """Ordered pairs (A, B) of disjoint sets of `pool` runs each, pooled."""
    groups = list(itertools.combinations(range(len(hs)), pool))
    return [(pooled([hs[i] for i in a]), pooled([hs[i] for i in b]), a, b)
            for a, b in itertools.permutations(groups, 2) if not set(a) & set(b)]


def planted(h, key, factor):
    out = copy.copy(h)
    out.values = dict(h.values)
    out.values[key] = {r: v * factor for r, v in h.values[key].items()}
    return out


def main(argv=None):
    ap = g.UsageParser(prog="python3 -m dbtools.track.power", description=__doc__.split("\n")[0], allow_abbrev=False)
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--slowdown", type=float, default=1.3, help="the planted slowdown factor (1.3)")
    ap.add_argument("--pool", type=int, default=1, help="runs joined into one side (1)")
    g.add_rule_options(ap)
    a = ap.parse_args(sys.argv[1:] if argv is None else argv)
    if a.pool < 1 or len(a.runs) < 2 * a.pool or a.slowdown <= 0:
        ap.error("needs at least 2 x --pool runs, --pool >= 1, --slowdown > 0")
    s = g.settings(ap, a)
    try:
        hs = [g.load_history(p) for p in a.runs]
    except g.InputError as e:
        print(f"power: error: {e}", file=sys.stderr)
        return 2
    caught = {"under 50 ms": [], "50 ms and over": []}
    alarms = 0
    pairs = sides(hs, a.pool)
    for base, now, ia, ib in pairs:
        tested = [c for c in g.compare(base, now, s) if c.cls == "cpu" and c.verdict in ("ok", "FAIL", "recorded only")]
        fails = [c for c in tested if c.verdict == "FAIL"]
        alarms += len(fails)
        print(f"runs {'+'.join(str(i + 1) for i in ia)} -> {'+'.join(str(i + 1) for i in ib)}: {len(tested)} CPU "
              f"comparisons, {len(fails)} fail" + "".join(f"; {c.cell} {c.measure} {c.ratio:.3f}" for c in fails))
        for c in tested:
            key = (c.cell, c.measure)
            one = g.Settings(**{**s.__dict__, "cells": (c.cell,), "measures": (c.measure,)})
            v = [x for x in g.compare(base, planted(now, key, a.slowdown), one) if x.measure == c.measure][0]
            caught["under 50 ms" if c.base < 0.05 else "50 ms and over"].append(v.verdict == "FAIL")
    every = [x for v in caught.values() for x in v]
    print(f"\nfalse alarms: {alarms} in {len(pairs)} ordered pairs ({a.pool} run(s) a side)")
    print(f"planted x{a.slowdown:g} slowdowns caught: " + ", ".join(
        f"{k} {statistics.mean(v):.2f} of {len(v)}" for k, v in caught.items() if v) +
        f"; all {statistics.mean(every):.2f}" if every else "no CPU-time comparison")
    return 0


if __name__ == "__main__":
    sys.exit(main())
