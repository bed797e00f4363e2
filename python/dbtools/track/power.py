"""The gate's false alarms and power on this machine's own noise: runs of ONE commit (records: history files of
experiments/track.cpp or bench_phases JSONs), gated side against side with gate.py's rules.

  python3 -m dbtools.track.power RUN RUN [RUN ...] [--pool K] [--any-sets | --interleaved] [--slowdown F]
                                 [gate options: --alpha P ...]

sides: by default `./run track`'s own: the runs given in the order they were taken, each K consecutive ones
  (--pool, default the driver's --runs default) one invocation of `./run track`, pooled (history.pooled), gated
  against every other invocation's K (the default baseline: the newest runs of the baseline commit); runs left
  over are named and left out. --any-sets: any disjoint sets of K runs against K (more pairs from the same runs,
  but not the default's sides: its K runs are taken back to back, under one load). --pool 1: one run a side.
  --interleaved: each 2K consecutive runs one invocation of `./run track --interleave` (B N B N ...): its alternate
  runs against each other, in both orders.
false alarms: every ordered pair of sides gated as they are: any FAIL is one (the runs are of one commit).
power: for each pair and each CPU-time measure the gate tests, that measure of the later side multiplied by F
  (--slowdown, 1.3) and gated again. Where the gate says it can fail a slowdown by F there (its resolution, the
  smallest slowdown it can fail: the threshold, --noise-k x the run-to-run spread, or the floor, is under F - 1),
  the share of the planted slowdowns that fail, by the phase's baseline median (under / over 50 ms) and in all,
  and the phases caught in fewer than 80% of the pairs where gateable, each with its share; the share over every
  planted slowdown, gateable or not; and the phases not gateable at F in some pairs, with what set the resolution.
The first line of the output names the configuration, and whether it is `./run track`'s default.
Exit: 0 (a measurement, not a gate), 1 usage, 2 unreadable history. Run with Debian's /usr/bin/python3.
"""
import copy
import itertools
import statistics
import sys
from dataclasses import dataclass, field

from . import gate as g
from .driver import DEFAULT_RUNS
from .history import pooled


def sides(hs, pool, any_sets=False, interleaved=False):
    """Ordered pairs (A, B, indices of A, indices of B) of disjoint sides of `pool` runs each, pooled: consecutive
    groups (one invocation each), or with `any_sets` any disjoint sets, or with `interleaved` the alternate runs of
    each group of 2 x `pool` consecutive runs (`./run track --interleave`: B N B N), in both orders."""
    def consecutive(k):
        return [tuple(range(i, i + k)) for i in range(0, len(hs) - k + 1, k)]

    if interleaved:
        pairs = [p for g in consecutive(2 * pool) for p in ((g[0::2], g[1::2]), (g[1::2], g[0::2]))]
    else:
        groups = list(itertools.combinations(range(len(hs)), pool)) if any_sets else consecutive(pool)
        pairs = [(a, b) for a, b in itertools.permutations(groups, 2) if not set(a) & set(b)]
    return [(pooled([hs[i] for i in a]), pooled([hs[i] for i in b]), a, b) for a, b in pairs]


def planted(h, key, factor):
    out = copy.copy(h)
    out.values = dict(h.values)
    out.values[key] = {r: v * factor for r, v in h.values[key].items()}
    return out


@dataclass
class Tally:
    """What power.py counts over the ordered pairs of sides."""
    alarms: int = 0        # pairs with a FAIL (the runs are of one commit: false alarms)
    fails: int = 0         # FAILs in all
    caught: dict = field(default_factory=lambda: {"under 50 ms": [], "50 ms and over": []})  # gateable: caught?
    every: list = field(default_factory=list)      # every planted slowdown, gateable or not: caught?
    by_phase: dict = field(default_factory=dict)   # (cell, measure) -> [caught?] where gateable
    ungateable: dict = field(default_factory=dict)  # (cell, measure) -> [what set the resolution] where not


def tally(pairs, s, slowdown):
    """Every pair gated as it is (false alarms), then each CPU time the gate tests planted `slowdown` times slower
    on the later side and gated again (power); a planted slowdown counts towards the power where the gate says it
    can fail one that size there (Comparison.gateable_at), and is listed with what set the resolution where not."""
    t = Tally()
    for base, now, ia, ib in pairs:
        tested = [c for c in g.compare(base, now, s) if c.cls == "cpu" and c.verdict in ("ok", "FAIL", "recorded only")]
        fails = [c for c in tested if c.verdict == "FAIL"]
        t.alarms, t.fails = t.alarms + bool(fails), t.fails + len(fails)
        print(f"runs {'+'.join(str(i + 1) for i in ia)} -> {'+'.join(str(i + 1) for i in ib)}: {len(tested)} CPU "
              f"comparisons, {len(fails)} fail" + "".join(f"; {c.cell} {c.measure} {c.ratio:.3f}" for c in fails))
        for c in tested:
            key = (c.cell, c.measure)
            one = g.Settings(**{**s.__dict__, "cells": (c.cell,), "measures": (c.measure,)})
            hit = [x for x in g.compare(base, planted(now, key, slowdown), one) if x.measure == c.measure][0]
            t.every.append(hit.verdict == "FAIL")
            if c.gateable_at(slowdown - 1):
                t.caught["under 50 ms" if c.base < 0.05 else "50 ms and over"].append(hit.verdict == "FAIL")
                t.by_phase.setdefault(key, []).append(hit.verdict == "FAIL")
            else:
                t.ungateable.setdefault(key, []).append(c.bound_by)
    return t


def report(t, a, n_pairs):
    x = f"x{a.slowdown:g}"
    print(f"\nfalse alarms: {t.alarms} in {n_pairs} ordered pairs ({a.pool} run(s) a side; pairs with a FAIL, "
          f"{t.fails} FAIL(s) in all)")
    gated = [hit for v in t.caught.values() for hit in v]
    print(f"planted {x} slowdowns caught where the gate can fail them (its resolution under {x}): " +
          "".join(f"{k} {share(v)}, " for k, v in t.caught.items() if v) + f"all {share(gated)}")
    print(f"planted {x} slowdowns caught, every gated comparison counted: {share(t.every)}; "
          f"{len(t.every) - len(gated)} of {len(t.every)} not gateable at {x}")
    weak = sorted((statistics.mean(v), k) for k, v in t.by_phase.items() if statistics.mean(v) < 0.8)
    print(f"phases caught in fewer than 80% of the pairs where gateable: {len(weak)} of {len(t.by_phase)}" +
          "".join(f"; {c} {m} {sum(t.by_phase[(c, m)])}/{len(t.by_phase[(c, m)])}" for _, (c, m) in weak))
    print(f"phases not gateable at {x} in some pairs (its resolution there set by): {len(t.ungateable)}" +
          "".join(f"; {c} {m} in {len(w)} of {n_pairs} ({', '.join(sorted(set(w)))})"
                  for (c, m), w in sorted(t.ungateable.items())))


def share(v):
    return f"{statistics.mean(v):.2f} of {len(v)}" if v else "none of 0"


def configuration(a, s, n):
    """The first line of the output: the sides, the rules, and whether this is `./run track`'s default."""
    default = a.pool == DEFAULT_RUNS and not a.any_sets and not a.interleaved and s == g.Settings()
    how = ("any disjoint sets" if a.any_sets else "alternate runs of one invocation, both orders (./run track "
           "--interleave)" if a.interleaved else "consecutive runs, one invocation of ./run track each")
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
    ap.add_argument("--interleaved", action="store_true", help="sides from the alternate runs of each 2 x --pool "
                    "consecutive runs, in both orders (./run track --interleave)")
    g.add_rule_options(ap)
    a = ap.parse_args(sys.argv[1:] if argv is None else argv)
    if a.pool < 1 or len(a.runs) < 2 * a.pool or a.slowdown <= 0 or (a.any_sets and a.interleaved):
        ap.error("needs at least 2 x --pool runs, --pool >= 1, --slowdown > 0; --any-sets or --interleaved")
    s = g.settings(ap, a)
    try:
        hs = [g.load_history(p) for p in a.runs]
    except g.InputError as e:
        print(f"power: error: {e}", file=sys.stderr)
        return 2
    print(configuration(a, s, len(hs)))
    group = 2 * a.pool if a.interleaved else a.pool
    left = [] if a.any_sets else a.runs[len(a.runs) - len(a.runs) % group:]
    if left:
        print(f"left out (not a whole side of {a.pool}): {', '.join(left)}")
    pairs = sides(hs, a.pool, a.any_sets, a.interleaved)
    report(tally(pairs, s, a.slowdown), a, len(pairs))
    return 0


if __name__ == "__main__":
    sys.exit(main())
