#!/usr/bin/env bash
# mpirun on one machine, as the tests and the examples of docs/mpi.md use it:
#   scripts/mpirun.sh N PROGRAM [ARGS...]
# N ranks, oversubscribed (more ranks than cores is fine for correctness), not bound to cores (a rank's BLAS threads
# may use every core; set OPENBLAS_NUM_THREADS to share them), and Open MPI's refusal to run as root lifted when
# root (--allow-run-as-root). MPIEXEC names another launcher (default: mpirun). Exit status: the program's, or
# mpirun's own when it fails to start the ranks.
set -euo pipefail
(($# >= 2)) || { echo "usage: scripts/mpirun.sh N PROGRAM [ARGS...]" >&2; exit 1; }
n=$1
shift
args=(--oversubscribe --bind-to none -np "$n")
if [ "$(id -u)" -eq 0 ]; then args=(--allow-run-as-root "${args[@]}"); fi
exec "${MPIEXEC:-mpirun}" "${args[@]}" "$@"
