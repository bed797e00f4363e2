"""The gate's false alarms and power on this machine's own noise: runs of ONE commit (records: history files of
experiments/track.cpp or bench_phases JSONs), gated side against side with gate.py's rules.

  python3 -m dbtools.track.power RUN RUN [RUN ...] [--pool K] [--any-sets] [--slowdown F] [gate options: --alpha P ...]

sides: by default `./run track`'s own: the runs given in the order they were taken, each K consecutive ones
  (--pool, default the driver's --runs default) one invocation of `./run track`, pooled (history.pooled), gated
  against every other invocation's K (the default baseline: the newest runs of the baseline commit); runs left
  over are named and left out. --any-sets: any disjoint sets of K runs against K (more pairs from the same runs,
  but not the default's sides: its K runs are taken back to back, under one load). --pool 1: one run a side.
false alarms: every ordered pair of sides gated as they are: any FAIL is one (the runs are of one commit).
power: for each pair and each CPU-time measure the gate tests, that measure of the later side multiplied by F
  (--slowdown, 1.3) and gated again: the share of planted slowdowns that fail, by the phase's baseline median
  (under / over 50 ms) and in all, and the phases caught in fewer than 80% of the pairs, each with its share.
The first line of the output names the configuration, and whether it is `./run track`'s default.
Exit: 0 (a measurement, not a gate), 1 usage, 2 unreadable history. Run with Debian's /usr/bin/python3.
"""
import copy
import itertools
import statistics
import sys

from . import gate as g
from .driver import DEFAULT_RUNS
from .history import pooled


def sides(hs, pool, any_sets=False):
    """Ordered pairs (A, B, indices of A, indices of B) of disjoint sides of `pool` runs each, pooled: consecutive
    groups (one invocation each), or with `any_sets` any disjoint sets."""
    if any_sets:
        groups = list(itertools.combinations(range(len(hs)), pool))
    else:
        groups = [tuple(range(i, i + pool)) for i in range(0, len(hs) - pool + 1, pool)]
    return [(pooled([hs[i] for i in a]), pooled([hs[i] for i in b]), a, b)
            for a, b in itertools.permutations(groups, 2) if not set(a) & set(b)]


def planted(h, key, factor):
    out = copy.copy(h)
    out.values = dict(h.values)
    out.values[key] = {r: v * factor for r, v in h.values[key].items()}
    return out


def configuration(a, s, n):
    """The first line of the output: the sides, the rules, and whether this is `./run track`'s default."""
    default = a.pool == DEFAULT_RUNS and not a.any_sets and s == g.Settings()
    how = "any disjoint sets" if a.any_sets else "consecutive runs, one invocation of ./run track each"
    rules = " ".join(g.rule_args(a))
    return (f"configuration: {a.pool} run(s) a side ({how}), rounds pooled; {n} run(s) given; gate rules {rules}: "
            + ("./run track's default (--runs and the default baseline)" if default else "NOT ./run track's default "
               f"(its default: {DEFAULT_RUNS} consecutive runs a side, the gate's default rules)"))


def main(argv=None):
    ap = g.UsageParser(prog="python3 -m dbtools.track.power", description=__doc__.split("\n")[0], allow_abbrev=False)
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--slowdown", type=float, default=1.3, help="the planted slowdown factor (1.3)")
    ap.add_argument("--pool", type=int, default=DEFAULT_RUNS, help=f"runs a side, pooled (./run track's --runs "
                    f"default, {DEFAULT_RUNS})")
    ap.add_argument("--any-sets", action="store_true", help="sides from any disjoint sets of --pool runs, not "
                    "consecutive ones")
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
    print(configuration(a, s, len(hs)))
    left = [] if a.any_sets else a.runs[len(a.runs) - len(a.runs) % a.pool:]
    if left:
        print(f"left out (not a whole side of {a.pool}): {', '.join(left)}")
    caught, by_phase = {"under 50 ms": [], "50 ms and over": []}, {}
    alarms, fails_all = 0, 0
    pairs = sides(hs, a.pool, a.any_sets)
    for base, now, ia, ib in pairs:
        tested = [c for c in g.compare(base, now, s) if c.cls == "cpu" and c.verdict in ("ok", "FAIL", "recorded only")]
        fails = [c for c in tested if c.verdict == "FAIL"]
        alarms, fails_all = alarms + bool(fails), fails_all + len(fails)
        print(f"runs {'+'.join(str(i + 1) for i in ia)} -> {'+'.join(str(i + 1) for i in ib)}: {len(tested)} CPU "
              f"comparisons, {len(fails)} fail" + "".join(f"; {c.cell} {c.measure} {c.ratio:.3f}" for c in fails))
        for c in tested:
            key = (c.cell, c.measure)
            one = g.Settings(**{**s.__dict__, "cells": (c.cell,), "measures": (c.measure,)})
            v = [x for x in g.compare(base, planted(now, key, a.slowdown), one) if x.measure == c.measure][0]
            caught["under 50 ms" if c.base < 0.05 else "50 ms and over"].append(v.verdict == "FAIL")
            by_phase.setdefault(key, []).append(v.verdict == "FAIL")
    every = [x for v in caught.values() for x in v]
    print(f"\nfalse alarms: {alarms} in {len(pairs)} ordered pairs ({a.pool} run(s) a side; pairs with a FAIL, "
          f"{fails_all} FAIL(s) in all)")
    print(f"planted x{a.slowdown:g} slowdowns caught: " + ", ".join(
        f"{k} {statistics.mean(v):.2f} of {len(v)}" for k, v in caught.items() if v) +
        f"; all {statistics.mean(every):.2f}" if every else "no CPU-time comparison")
    weak = sorted((statistics.mean(v), k) for k, v in by_phase.items() if statistics.mean(v) < 0.8)
    print(f"phases caught in fewer than 80% of the pairs: {len(weak)} of {len(by_phase)}" +
          "".join(f"; {c} {m} {sum(by_phase[(c, m)])}/{len(by_phase[(c, m)])}" for _, (c, m) in weak))
    return 0


if __name__ == "__main__":
    sys.exit(main())
