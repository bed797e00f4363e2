#!/usr/bin/env bash
# The experiments ./run reproduce runs, in order. Each driver writes results/<name>.csv (atomically).
# usage: scripts/experiments.sh BUILD_DIR [--full]
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=$1; shift
FULL=${1:-}
log() { printf '[experiments] %s\n' "$*" >&2; }

log "deform cases (BS08 + bundled cactus, lap and tf)"
"$BUILD/exp_deform_cases" --data "$ROOT/data" --shared "$ROOT/../shared/data/bs08" \
  --out "$ROOT/results/deform_cases.csv" --meshes "$ROOT/results/meshes"
