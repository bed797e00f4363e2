#!/usr/bin/env bash
# The step after the drivers (./run reproduce): every plot, then every report. The reports cite the figures and
# say which are missing, so they are written once, after all the plots.
# usage: scripts/reports.sh RESULTS_DIR PLOTS_DIR [PYTHON]   (PYTHON: one with numpy + matplotlib, default
#        /usr/bin/python3, Debian's)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
RESULTS=$1
PLOTS=$2
PY=${3:-/usr/bin/python3}
log() { printf '[reports] %s\n' "$*" >&2; }

mkdir -p "$PLOTS"
log "plots with $PY (CSVs of $RESULTS -> $PLOTS)"
for s in "$ROOT"/plots/*.py; do
  case $(basename "$s") in styles.py) continue ;; esac  # the plots' shared style table, not a plot
  "$PY" "$s" --results "$RESULTS" --out "$PLOTS"
done
log "reports with $PY ($RESULTS/*.md from the CSVs, citing $PLOTS)"
"$PY" "$ROOT/experiments/reports/report.py" --results "$RESULTS" --plots "$PLOTS"
