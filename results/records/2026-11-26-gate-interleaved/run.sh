#!/bin/bash
# `./run track --baseline REV --interleave`'s sides measured on runs of one commit (issue 32, item 4): INVOCATIONS
# times four runs back to back (B N B N: the baseline's and the run's alternated; one commit, so both are this
# tree's exp_track), taken by the gate-default record's script (its loads beside: none, a busy loop, a build; its lock),
# then each invocation's runs 1+3 gated against 2+4 and 2+4 against 1+3, pooled, and a x1.3 slowdown planted into
# each gated CPU time in turn (dbtools.track.power --interleaved), by the default rule and by the former one.
#   results/records/2026-11-26-gate-interleaved/run.sh   (OUT=/tmp/gate-interleave INVOCATIONS=5: the record)
set -u
cd "$(dirname "$0")/../../.."
R=results/records/2026-11-26-gate-interleaved
OUT=${OUT:-/tmp/gate-interleave} INVOCATIONS=${INVOCATIONS:-5}
OUT=$OUT INVOCATIONS=$INVOCATIONS RUNS=4 RUNS_ONLY=1 bash results/records/2026-11-26-gate-default/run.sh
runs=$(for n in $(seq 1 $((4 * INVOCATIONS))); do echo "$OUT/run$n.csv"; done)
export PYTHONPATH=$PWD/python
/usr/bin/python3 -m dbtools.track.power $runs --interleaved >"$OUT/power_interleaved.txt"
/usr/bin/python3 -m dbtools.track.power $runs --interleaved --noise-k 0 >"$OUT/power_interleaved_k0.txt"
# For comparison, on the same runs: the default's sides (each invocation's first two runs, consecutive, against
# another invocation's), as ./run track gates a baseline measured earlier.
first=$(for i in $(seq 1 "$INVOCATIONS"); do for k in 1 2; do echo "$OUT/run$((4 * (i - 1) + k)).csv"; done; done)
/usr/bin/python3 -m dbtools.track.power $first >"$OUT/power_consecutive.txt"
cp "$OUT"/power_*.txt "$OUT/runs.log" "$R/"
for n in $(seq 1 $((4 * INVOCATIONS))); do xz -c "$OUT/run$n.csv" >"$R/run$n.csv.xz"; done
