#!/bin/bash
# The default gate of `./run track` (2 runs a side, pooled: python/dbtools/track/driver.py) measured on runs of one
# commit: INVOCATIONS times the two back-to-back runs one `./run track` makes (the driver's exp_track command, a subset
# of the suite), each invocation with its load beside it (LOADS: none, a busy loop `yes`, or a build: g++ compiling
# one of the project's sources over and over), then every ordered pair of invocations gated as `./run track` gates
# them, and a x1.3 slowdown planted into each gated CPU time in turn (python/dbtools/track/power.py, whose default is
# that configuration). QUIET: a file whose presence means another measurement needs the machine (this box's lock):
# no run starts while it exists, and the load beside a run stops when it appears.
#   results/records/2026-11-26-gate-default/run.sh      (OUT=/tmp/gate-runs INVOCATIONS=5 by default: the record)
# Runs already in OUT are kept (a longer series continues a shorter one: INVOCATIONS=7 after 5). RUNS (default 2):
# runs per invocation; RUNS_ONLY: stop after the runs (the later gate records take their runs with this script and
# analyse them their own way: 2026-11-26-gate-rule, 2026-11-26-gate-interleaved).
set -u
cd "$(dirname "$0")/../../.."   # the repository root, with build/exp_track built (Release)
C=$(git rev-parse HEAD)
export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 DEFORMBENCH_THREADS=1 DEFORMBENCH_SOURCE_DIR=$PWD
export DEFORMBENCH_GIT_SHA=${C:0:12}
OUT=${OUT:-/tmp/gate-runs}
INVOCATIONS=${INVOCATIONS:-5}
RUNS=${RUNS:-2}
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
[ -n "${RUNS_ONLY:-}" ] && exit 0
export PYTHONPATH=$PWD/python
runs=$(for n in $(seq 1 $((2 * INVOCATIONS))); do echo "$OUT/run$n.csv"; done)
# ./run track's default sides: each invocation's two runs, pooled, against another invocation's two.
/usr/bin/python3 -m dbtools.track.power $runs >"$OUT/power_default.txt"
# For comparison, from the same runs: one run a side (every ordered pair of runs; what `./run track --runs 1` gates).
/usr/bin/python3 -m dbtools.track.power $runs --pool 1 >"$OUT/power_one.txt"
