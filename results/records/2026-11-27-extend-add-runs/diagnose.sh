#!/usr/bin/env bash
# Where the 104k TF factorization's dense work goes: a build with blas_calls.patch (applies to the commit in
# README.md) times each kind of BLAS/LAPACK call of the fronts, summed over the threads. RUNS runs at 1 and at 2
# threads, each right after a process that wrote and freed 2 GB (as run.sh). Writes blas_calls.txt here.
# usage: results/records/2026-11-27-extend-add-runs/diagnose.sh DIAG_BINARY [RUNS]   (from the repository root)
set -euo pipefail
diag=$1 runs=${2:-3}
here=$(cd "$(dirname "$0")" && pwd)
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
for threads in 1 2; do
  for ((k = 1; k <= runs; k++)); do
    export DEFORMBENCH_THREADS=$threads OPENBLAS_NUM_THREADS=$threads
    build/exp_machine_rates --first-touch-mb 2048 >/dev/null
    "$diag" deform data/edits/armadillo_loop1_whole.edit --method tf --constraints soft --frames 1 \
      --out "$t/o.ply" --csv "$t/o.csv" 2>"$t/err" >/dev/null
    echo "threads $threads, run $k: factorize_s $(/usr/bin/python3 -c "import csv, sys; print(list(csv.DictReader(open(sys.argv[1])))[0]['factorize_s'])" "$t/o.csv")"
    grep BLAS_CALLS "$t/err" | sed 's/^BLAS_CALLS /  /'
  done
done | tee "$here/blas_calls.txt"
