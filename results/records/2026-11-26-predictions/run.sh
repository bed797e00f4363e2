#!/usr/bin/env bash
# Issue 30 items 1-2: the calibration, the predicted-against-measured cells, the report, advise on CGAL's bull and
# the --scale check. Run from the repository root after building deformbench, meshtool and exp_predictions, with
# data/meshes in place (scripts/data.sh) and bull.off beside this script (see README.md).
set -euo pipefail
R=results/records/2026-11-26-predictions
OUT=${OUT:-/tmp/predictions}
mkdir -p "$OUT"
build/deformbench advise --calibrate 2>"$R/calibrate.log"
cp build/machine_calibration.csv "$R/"
build/exp_predictions --results "$OUT" --timeout-s 60 2>"$R/run.log"
cp "$OUT/predictions.csv" "$R/"
PYTHONPATH=python /usr/bin/python3 -m dbtools.report --results "$OUT" --only predictions
cp "$OUT/predictions.md" "$R/"; cp "$OUT/figures/predictions.png" "$R/"
build/deformbench advise "$R/bull.edit" --method tf --frames 10 --csv "$R/bull_advise.csv" \
  >"$R/bull_advise.txt" 2>"$R/bull_advise.log"
build/deformbench advise data/edits/armadillo_whole.edit --method tf --constraints soft --predict-only --scale 4 \
  --backends multifrontal --csv "$R/scale_predicted.csv" >"$R/scale_predicted.txt"
build/deformbench advise data/edits/armadillo_loop1_whole.edit --method tf --constraints soft --quick --frames 1 \
  --backends multifrontal --csv "$R/scale_measured.csv" >"$R/scale_measured.txt" 2>&1
