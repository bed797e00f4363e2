#!/usr/bin/env bash
# The MUMPS-on-ranks measurements of results/records/2026-11-24-mumps-ranks/ (build/exp_mumps_ranks; experiments/mumps_ranks.cpp).
#   scripts/mumps_ranks.sh solve MESH OUT.csv [ROUNDS]     multifrontal, mumps on 1 rank, mumps on 2 ranks,
#                                                           interleaved, ROUNDS times (default 2)
#   scripts/mumps_ranks.sh analysis MESH OUT.csv ["NP..."]  MUMPS's analysis only on each NP ranks (default
#                                                           "1 2 3 4 5 6 7 8"); rank 0 passes every entry
#   scripts/mumps_ranks.sh threads MESH OUT.csv [ROUNDS]   mumps on 1 rank with every core's BLAS thread, on 1
#                                                           rank with 1 BLAS thread, on 2 ranks, interleaved
#   scripts/mumps_ranks.sh estimate MESH OUT.csv ["NP..."]  MUMPS's analysis only on each NP ranks (default
#                                                           "1 2 4 8"): rank 0 alone builds the pattern and passes
#                                                           it as centralized input; the other ranks mostly wait,
#                                                           and yield their core while they do (Open MPI's
#                                                           mpi_yield_when_idle; at nice 19 they answered so late
#                                                           that the 104k analysis on 4 ranks took twice as long)
# Every run is one row of OUT.csv (rows appended in run order, one header). Threads: the one-process runs use
# the machine's cores (BLAS and the multifrontal's threads); on N ranks each rank's BLAS gets cores/N threads, at
# least 1, so the ranks share the cores rather than oversubscribe them. The 2-rank solutions are compared with
# the multifrontal one of the same round (max_diff_vs_compare, units of the bounding-box diagonal).
set -euo pipefail
(($# >= 3)) || { sed -n 2,16p "$0" >&2; exit 1; }
mode=$1 mesh=$2 out=$3
ROOT=$(cd "$(dirname "$0")/.." && pwd)
EXE=$ROOT/build/exp_mumps_ranks
[ -x "$EXE" ] || { echo "mumps_ranks.sh: $EXE not built" >&2; exit 1; }
cores=$(nproc)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
k=0
row() { # NP ARGS...: one run into the next row file (NP 0: one process, no launcher); BLAS_THREADS overrides
  local np=$1; shift
  k=$((k + 1))
  local threads=${BLAS_THREADS:-$((cores / (np > 0 ? np : 1)))}; ((threads >= 1)) || threads=1
  echo "[mumps_ranks.sh] np=$np blas_threads=$threads $* (load $(cut -d' ' -f1-3 /proc/loadavg))" >&2
  if ((np == 0)); then OPENBLAS_NUM_THREADS=$threads "$EXE" --mesh "$mesh" "$@" --csv "$tmp/$k.csv" >&2
  else OPENBLAS_NUM_THREADS=$threads "$ROOT/scripts/mpirun.sh" "$np" "$EXE" --mesh "$mesh" "$@" --csv "$tmp/$k.csv" >&2
  fi
}
case $mode in
  solve)
    for ((r = 1; r <= ${4:-2}; ++r)); do
      row 0 --solver multifrontal --positions "$tmp/mf.bin" --label "$(basename "$mesh" .off)"
      row 1 --compare "$tmp/mf.bin"
      row 2 --compare "$tmp/mf.bin"
    done ;;
  threads)
    for ((r = 1; r <= ${4:-2}; ++r)); do
      row 1
      BLAS_THREADS=1 row 1
      row 2
    done ;;
  analysis)
    for np in ${4:-1 2 3 4 5 6 7 8}; do row "$np" --analysis-only --input root; done ;;
  estimate)
    export OMPI_MCA_mpi_yield_when_idle=${OMPI_MCA_mpi_yield_when_idle:-1}
    for np in ${4:-1 2 4 8}; do BLAS_THREADS=1 row "$np" --analysis-only --input centralized; done ;;
  *) echo "mumps_ranks.sh: mode is solve, threads, analysis or estimate" >&2; exit 1 ;;
esac
/usr/bin/python3 - "$out" "$tmp" "$k" <<'EOF'
import csv, os, sys
out, tmp, k = sys.argv[1], sys.argv[2], int(sys.argv[3])
rows = [r for i in range(1, k + 1) for r in csv.DictReader(open(os.path.join(tmp, f"{i}.csv"), newline=""))]
cols = []
for r in rows:
    cols += [c for c in r if c not in cols]
with open(out + ".tmp", "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=cols, restval="")
    w.writeheader()
    w.writerows(rows)
os.replace(out + ".tmp", out)
EOF
echo "[mumps_ranks.sh] wrote $out ($k rows)" >&2
