#!/usr/bin/env bash
# The measurements ./run reproduce runs, in order. Each driver reads its config (data/experiments/NAME.toml) and
# writes CSVs only (atomically) under results/; ./run then runs the report step (python3 -m dbtools.report), which
# draws the figures into results/figures/ and, after them, writes the Markdown reports from the CSVs. A driver that fails (exit 5: a cell failed, its other cells written; or any other error)
# does not stop the others: every driver runs, then the script exits with the first failure's code, naming every
# failed driver on stderr and, when EXPERIMENTS_FAILED names a file, in that file (one line each).
# usage: scripts/experiments.sh BUILD_DIR [--full]
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=$1; shift
FULL=${1:-}
CONF=$ROOT/data/experiments
log() { printf '[experiments] %s\n' "$*" >&2; }
FAILED=() FIRST_RC=0
# step NAME COMMAND...: runs one driver, remembering a failure.
step() {
  local name=$1 rc=0
  shift
  "$@" || rc=$?
  ((rc == 0)) && return 0
  FAILED+=("exp_$name (exit $rc)")
  ((FIRST_RC)) || FIRST_RC=$rc
  log "exp_$name FAILED (exit $rc); the next drivers still run"
}

log "deform cases (BS08 + bundled cactus, lap and tf)"
step deform_cases "$BUILD/exp_deform_cases" --config "$CONF/deform_cases.toml" --data "$ROOT/data" \
  --out "$ROOT/results/deform_cases.csv" --meshes "$ROOT/results/meshes"

# Thesis Table 2-1: every cell in fresh child processes under a memory budget (default half the RAM) and a time
# budget (default 120 s a cell, --full 900 s) checked on predictions; about 5 minutes on 2 cores (--full adds
# armadillo Loop levels 2-3, up to 1.66M vertices).
log "table 2-1 (dense / naive / structured builds of LAP and TF; scaling of the structured build)"
step table_2_1 "$BUILD/exp_table_2_1" --config "$CONF/table_2_1.toml" --data "$ROOT/data" --results "$ROOT/results" \
  ${FULL:+--full}

# Solver choice: backends x orderings on the LAP and TF systems, and the BLAS kernel set. OPENBLAS_CORETYPE is read
# when OpenBLAS loads, so each kernel set is its own driver run: first the other kernel sets (BLAS-calling backends
# only, plus Eigen's dense LLT as a no-BLAS control) into results/solvers_blas_CORE.csv, then the full grid under
# this run's setting into results/solvers.csv; the report compares them. A setting runs only when the core OpenBLAS
# reports under it (`deformbench provenance`) loads a kernel set no other run has (data/experiments/
# blas_kernel_sets.txt): two runs of one set would show the noise between them as a kernel effect. The rows say
# which setting each run had (blas_coretype_env) and the core it loaded (blas_core).
log "solver choice (backends x orderings; BLAS kernel sets)"
SOLV=("$BUILD/exp_solvers" --config "$CONF/solvers.toml" --data "$ROOT/data" --results "$ROOT/results")
[ "$FULL" = --full ] && SOLV+=(--full)
SOLV_BLAS_BACKENDS=cholmod_supernodal,multifrontal,umfpack,dense_llt,lapack_potrf,dense_ldlt_bk,dense_lu
rm -f "$ROOT"/results/solvers_blas_*.csv
# with_coretype SETTING CMD...: CMD under OPENBLAS_CORETYPE=SETTING (empty SETTING: unset, OpenBLAS' own detection).
with_coretype() {
  local setting=$1; shift
  if [ -n "$setting" ]; then env OPENBLAS_CORETYPE="$setting" "$@"; else env -u OPENBLAS_CORETYPE "$@"; fi
}
# blas_core SETTING: the core OpenBLAS loads under it, as result rows record it (blas_core).
blas_core() { with_coretype "$1" "$BUILD/deformbench" provenance | sed -n 's/^blas_core: //p'; }
# kernel_set CORE: the kernel set the core loads (data/experiments/blas_kernel_sets.txt; else the core itself).
kernel_set() { awk -v c="$1" '!/^#/ && $1 == c { s = $2 } END { print (s != "" ? s : c) }' "$CONF/blas_kernel_sets.txt"; }
SETS_RUN=" $(kernel_set "$(blas_core "${OPENBLAS_CORETYPE:-}")") "
SETTINGS=("")  # OpenBLAS' own detection, then the kernel sets this CPU can run
grep -qw avx512f /proc/cpuinfo && SETTINGS+=(SkylakeX)
grep -qw avx2 /proc/cpuinfo && SETTINGS+=(Haswell)
for setting in "${SETTINGS[@]}"; do
  core=$(blas_core "$setting")
  kset=$(kernel_set "$core")
  if [ -z "$core" ] || [[ "$SETS_RUN" == *" $kset "* ]]; then
    log "OPENBLAS_CORETYPE=${setting:-<unset>} loads core ${core:-?} ($kset kernels), already measured: not run again"
    continue
  fi
  SETS_RUN+="$kset "
  log "solver choice under OPENBLAS_CORETYPE=${setting:-<unset>} (core $core, $kset kernels)"
  step "solvers (OPENBLAS_CORETYPE=${setting:-<unset>})" with_coretype "$setting" "${SOLV[@]}" \
    --backends "$SOLV_BLAS_BACKENDS" --orderings default --out "$ROOT/results/solvers_blas_$core.csv"
done
log "solver choice, full grid (OPENBLAS_CORETYPE=${OPENBLAS_CORETYPE:-<unset>})"
step solvers "${SOLV[@]}"

# LRI and the frames experiment: bends, twists, the dino head turn and the BS08 edits for lap, tf and lri x frame
# strategy x orthonormalization; deformed meshes under results/meshes/frames for the renders.
log "frames (LRI frame strategies against lap and tf)"
step frames "$BUILD/exp_frames" --config "$CONF/frames.toml" --data "$ROOT/data" --out "$ROOT/results/frames.csv" \
  --meshes "$ROOT/results/meshes/frames"

# The LSE report's other applications: coating transfer and transplanting on the BS08 plane, the CGAL bunny and a
# procedural plane; meshes for the renders (dbtools/plots/applications.py).
log "applications (coating transfer, transplanting)"
step applications "$BUILD/exp_applications" --config "$CONF/applications.toml" --data "$ROOT/data" \
  --out "$ROOT/results/applications.csv" --meshes "$ROOT/results/meshes/applications"

if ((${#FAILED[@]})); then
  log "failed: ${FAILED[*]}"
  [ -z "${EXPERIMENTS_FAILED:-}" ] || printf '%s\n' "${FAILED[@]}" >"$EXPERIMENTS_FAILED"
  exit "$FIRST_RC"
fi
