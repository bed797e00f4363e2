#!/bin/bash
# Five runs of a subset of the tracking suite (the armadillo LAP solve cells, the hand deformation cells) at one
# commit, back to back; runs 4 and 5 with a busy loop (`yes`) beside them. Then the gate's false alarms and power
# (python/dbtools/track/power.py) on every ordered pair, one run a side and two runs a side (--pool 2).
# Run 1 was started by hand with the same command as the loop's body.
set -u
cd "$(dirname "$0")/../../.."   # the repository root, with build/exp_track built (Release)
C=$(git rev-parse HEAD)
export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 DEFORMBENCH_THREADS=1 DEFORMBENCH_SOURCE_DIR=$PWD
export DEFORMBENCH_GIT_SHA=${C:0:12}
OUT=${OUT:-/tmp/gate-study}
mkdir -p "$OUT"
for k in 1 2 3 4 5; do
  busy=""
  if [ $k -ge 4 ]; then yes >/dev/null & busy=$!; fi
  s=$(date +%s); echo "run $k start $(date -u +%T) load $(cut -d' ' -f1-3 /proc/loadavg) busy=${busy:-none}" >>"$OUT/runs.log"
  ./build/exp_track --data data --only 'solve/armadillo/lap/*,deform/hand/*' --commit "$C" --out "$OUT/run$k.csv" \
    >"$OUT/run$k.log" 2>&1
  echo "run $k rc=$? wall=$(($(date +%s) - s)) end load $(cut -d' ' -f1-3 /proc/loadavg)" >>"$OUT/runs.log"
  [ -n "$busy" ] && kill "$busy"
done
export PYTHONPATH=$PWD/python
/usr/bin/python3 -m dbtools.track.power "$OUT"/run{1,2,3,4,5}.csv >"$OUT/power.txt"
/usr/bin/python3 -m dbtools.track.power "$OUT"/run{1,2,3,4,5}.csv --pool 2 >"$OUT/power_pool2.txt"
