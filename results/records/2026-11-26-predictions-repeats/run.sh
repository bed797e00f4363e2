#!/usr/bin/env bash
# Issue 30 item 2 after the predictor's last changes (the build per vertex ordering, --scale by subdivision, short
# cells measured three times): the calibration, the predicted-against-measured cells of Table 2-1 and the solver
# study, the report, and the --scale check (416k predicted from the 104k edit x 4, then measured three times on the
# 416k twin). From the repository root after building deformbench, meshtool and exp_predictions, with data/meshes,
# data/generated/armadillo_loop1.off and armadillo_loop2.off in place (scripts/data.sh --full).
set -euo pipefail
R=results/records/2026-11-26-predictions-repeats
OUT=${OUT:-/tmp/predictions-repeats}
mkdir -p "$OUT"
load() { echo "$(date -u +%T) load $1: $(cut -d' ' -f1-3 /proc/loadavg)" >> "$R/load.log"; }
: > "$R/load.log"
load "before the calibration"
build/deformbench advise --calibrate 2>"$R/calibrate.log"
cp build/machine_calibration.csv "$R/"
load "before the cells"
build/exp_predictions --results "$OUT" --timeout-s 60 2>"$R/run.log"
cp "$OUT/predictions.csv" "$R/"
load "after the cells"
PYTHONPATH=python /usr/bin/python3 -m dbtools.report --results "$OUT" --only predictions
cp "$OUT/predictions.md" "$R/"; cp "$OUT/figures/predictions.png" "$R/"
build/deformbench advise data/edits/armadillo_loop1_whole.edit --method tf --constraints soft --predict-only \
  --scale 4 --backends multifrontal --csv "$R/scale_predicted.csv" >"$R/scale_predicted.txt" 2>&1
for k in 1 2 3; do
  load "before the 416k runs, round $k"
  build/deformbench advise data/edits/armadillo_loop2_whole.edit --method tf --constraints soft --quick --frames 1 \
    --backends multifrontal --csv "$R/scale_measured_$k.csv" >"$R/scale_measured_$k.txt" 2>&1
done
load "after the 416k runs"
