"""Diagnostic, offline (not the gate's default): sides taken within one invocation - its runs 1 and 3 pooled
against its run 2, in both orders - so that both sides' rounds come from the same few minutes, as paired,
interleaved runs of two commits would. Invocations 1 and 6, which the lock split, are left out. Power and false
alarms counted as power.py counts them, with the gate's default rules (--noise-k K: argv[2], default 2).

  R=results/records/2026-11-26-gate-rule; (cd $R && xz -dk run*.csv.xz)
  PYTHONPATH=python /usr/bin/python3 $R/within_invocation.py $R [K] > $R/power_within_invocation[_k0].txt
"""
import argparse
import os
import sys

from dbtools.track import gate as g
from dbtools.track import power as pw
from dbtools.track.history import pooled

SPLIT = {1, 6}  # invocations the lock split: their runs are not minutes apart


def main():
    d = sys.argv[1]
    k = float(sys.argv[2]) if len(sys.argv) > 2 else g.Settings().noise_k
    runs = [g.load_history(os.path.join(d, f"run{i}.csv")) for i in range(1, 25)]
    pairs = []
    for inv in range(8):
        if inv + 1 in SPLIT:
            continue
        i = 3 * inv
        aba, b = pooled([runs[i], runs[i + 2]]), pooled([runs[i + 1]])
        pairs += [(aba, b, (i, i + 2), (i + 1,)), (b, aba, (i + 1,), (i, i + 2))]
    print(f"configuration: within one invocation (runs 1+3 against run 2, both orders), invocations "
          f"{sorted(set(range(1, 9)) - SPLIT)}; gate rules --noise-k {k:g}, the rest the defaults")
    pw.report(pw.tally(pairs, g.Settings(noise_k=k), 1.3), argparse.Namespace(slowdown=1.3, pool="1 or 2"), len(pairs))


if __name__ == "__main__":
    main()
