#!/usr/bin/env bash
# Issue 30 item 2 after the predictor's last changes (the build per vertex ordering, --scale by subdivision, short
# runs measured three times, the factorization's rate capped at the dense Cholesky's): the earlier record's script
# (calibration, the predicted-against-measured cells, the report, the --scale prediction) with the 416k twin measured
# three times. From the repository root, prerequisites as that script says.
RECORD_DIR=results/records/2026-11-26-predictions-repeats ROUNDS=3 OUT=${OUT:-/tmp/predictions-repeats} \
  exec bash "$(dirname "$0")/../2026-11-26-predictions-quiet/run.sh"
