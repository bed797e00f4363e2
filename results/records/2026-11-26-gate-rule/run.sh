#!/bin/bash
# The gate's rule chosen on the runs of record 2026-11-26-gate-default, validated on new runs of one commit:
# INVOCATIONS times the RUNS back-to-back runs one `./run track` makes (the driver's exp_track command, a subset of
# the suite), each invocation with its load beside it (LOADS: none, a busy loop `yes`, or a build: g++ compiling one
# of the project's sources over and over), then every ordered pair of invocations gated as `./run track` gates them,
# and a x1.3 slowdown planted into each gated CPU time in turn (python/dbtools/track/power.py, whose default is that
# configuration). QUIET: a file whose presence means another measurement needs the machine (this box's lock): no
# run starts while it exists, and the load beside a run stops when it appears.
#   results/records/2026-11-26-gate-rule/run.sh      (OUT=/tmp/gate-rule-runs INVOCATIONS=8 RUNS=3: the record)
# Runs already in OUT are kept (a longer series continues a shorter one). Writes into OUT: runN.csv / runN.log (runs
# 3i-2 .. 3i are invocation i), runs.log, and the power_*.txt outputs of the lines at the end (the default on each
# invocation's first two runs; the former rule, three runs a side and the diagnostic normalized_only.py for
# comparison; the same on the runs of record 2026-11-26-gate-default, which the rule was chosen on).
set -u
cd "$(dirname "$0")/../../.."   # the repository root, with build/exp_track built (Release)
OUT=${OUT:-/tmp/gate-rule-runs}
INVOCATIONS=${INVOCATIONS:-8}
RUNS=${RUNS:-3}
# The runs, with their loads and the lock, as the gate-default record takes them.
OUT=$OUT INVOCATIONS=$INVOCATIONS RUNS=$RUNS RUNS_ONLY=1 bash results/records/2026-11-26-gate-default/run.sh
export PYTHONPATH=$PWD/python
runs=() first=()
for i in $(seq 1 "$INVOCATIONS"); do
  for k in $(seq 1 "$RUNS"); do
    n=$((RUNS * (i - 1) + k)); runs+=("$OUT/run$n.csv")
    [ "$k" -le 2 ] && first+=("$OUT/run$n.csv")
  done
done
# ./run track's default sides (2 runs a side: each invocation's first two runs, pooled, against another's), the
# default rule; then the same sides under the former rule (--noise-k 0: the threshold alone), for comparison.
/usr/bin/python3 -m dbtools.track.power "${first[@]}" >"$OUT/power_default.txt"
/usr/bin/python3 -m dbtools.track.power "${first[@]}" --noise-k 0 >"$OUT/power_former_rule.txt"
# Three runs a side (every run of an invocation; ./run track --runs 3), the default rule.
/usr/bin/python3 -m dbtools.track.power "${runs[@]}" --pool 3 >"$OUT/power_three.txt"
# The runs the rule was chosen on (record 2026-11-26-gate-default, five invocations of two runs), the default rule.
old=results/records/2026-11-26-gate-default
mkdir -p "$OUT/chosen-on"
for n in $(seq 1 10); do xz -d -c "$old/run$n.csv.xz" >"$OUT/chosen-on/run$n.csv"; done
/usr/bin/python3 -m dbtools.track.power "$OUT"/chosen-on/run{1..10}.csv >"$OUT/power_chosen_on.txt"
# A diagnostic, not the project's rule (normalized_only.py beside this file): CPU time decided on the drift-normalized
# medians alone, on the new runs' default sides and on the runs the rule was chosen on.
/usr/bin/python3 results/records/2026-11-26-gate-rule/normalized_only.py "${first[@]}" >"$OUT/power_normalized_only.txt"
/usr/bin/python3 results/records/2026-11-26-gate-rule/normalized_only.py "$OUT"/chosen-on/run{1..10}.csv \
  >"$OUT/power_normalized_only_chosen_on.txt"
# How the rule was chosen: --noise-k over the runs of record 2026-11-26-gate-default (0: the former rule).
for k in 0 1 1.5 3; do
  /usr/bin/python3 -m dbtools.track.power "$OUT"/chosen-on/run{1..10}.csv --noise-k $k >"$OUT/power_chosen_on_k$k.txt"
done
