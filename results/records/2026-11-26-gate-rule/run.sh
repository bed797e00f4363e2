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
C=$(git rev-parse HEAD)
export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 DEFORMBENCH_THREADS=1 DEFORMBENCH_SOURCE_DIR=$PWD
export DEFORMBENCH_GIT_SHA=${C:0:12}
OUT=${OUT:-/tmp/gate-rule-runs}
INVOCATIONS=${INVOCATIONS:-8}
RUNS=${RUNS:-3}
QUIET=${QUIET:-/work/notes/QUIET}
LOADS=(none yes build none yes build)
ONLY='solve/armadillo/lap/*,deform/hand/*'
mkdir -p "$OUT"
log() { echo "$*" >>"$OUT/runs.log"; }

start_load() {  # start_load KIND: the load's process group runs in the background; its pid in $load
  load=""
  case $1 in
    yes) setsid yes >/dev/null & load=$! ;;
    build) # one of the project's larger sources compiled again and again, without ccache, as a build would
      setsid bash -c 'while :; do g++ -std=gnu++17 -O3 -DNDEBUG -DFMT_SHARED -I"$0/src/deformbench" -I"$0" \
        -isystem /usr/include/eigen3 -isystem /usr/include/suitesparse -c "$0/src/deformbench/methods/deformer.cpp" \
        -o /tmp/gate-load-$$.o 2>/dev/null; done' "$PWD" & load=$! ;;
  esac
  # The load stops when the lock appears (a quieter run then, said in runs.log).
  [ -n "$load" ] && { (while kill -0 "$load" 2>/dev/null; do
      [ -e "$QUIET" ] && { log "load $load stopped: $QUIET appeared $(date -u +%T)"; kill -- -"$load"; }
      sleep 5; done) & }
}

load=""
for i in $(seq 1 "$INVOCATIONS"); do
  kind=${LOADS[$(((i - 1) % ${#LOADS[@]}))]}
  for k in $(seq 1 "$RUNS"); do
    n=$((RUNS * (i - 1) + k))
    [ -s "$OUT/run$n.csv" ] && continue
    while [ -e "$QUIET" ]; do sleep 15; done
    { [ -n "$load" ] && kill -0 "$load" 2>/dev/null; } || start_load "$kind"
    s=$(date +%s)
    log "invocation $i run $k (run$n) start $(date -u +%T) load $(cut -d' ' -f1-3 /proc/loadavg) beside: $kind"
    ./build/exp_track --config data/experiments/track.toml --data data --commit "$C" --out "$OUT/run$n.csv" \
      --mesh-cache "$OUT/meshes" --only "$ONLY" >"$OUT/run$n.log" 2>&1
    log "run$n rc=$? wall=$(($(date +%s) - s)) s end $(date -u +%T) load $(cut -d' ' -f1-3 /proc/loadavg)"
  done
  [ -n "$load" ] && kill -- -"$load" 2>/dev/null
  load=""
done
# RUNS_ONLY: stop here (another record analyses the runs: 2026-11-26-gate-interleaved).
[ -n "${RUNS_ONLY:-}" ] && exit 0
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
