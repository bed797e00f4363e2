#!/usr/bin/env bash
# Issue 30 item 3 on 2 cores: does CHOLMOD's OpenMP beside OpenBLAS's own threads slow its factorization (the
# mechanism suspected behind its collapse at 16 threads on a 16-core machine)? CHOLMOD supernodal on the 104k TF
# edit (soft), one frame, fresh process per run, under thread settings that differ only in OpenMP's:
#   t1           OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1
#   omp2         OPENBLAS_NUM_THREADS=2 OMP_NUM_THREADS=2   (what `deform`, `advise --threads 2` and
#                                                           scripts/device_threads.sh set)
#   omp_unset    OPENBLAS_NUM_THREADS=2, OMP_NUM_THREADS unset (a user's shell)
#   omp1         OPENBLAS_NUM_THREADS=2 OMP_NUM_THREADS=1   (experiments/harness/thread_policy.h for cholmod_*)
#   passive      OPENBLAS_NUM_THREADS=2 OMP_NUM_THREADS=2 OMP_WAIT_POLICY=passive (idle OpenMP threads sleep)
#   limit1       OPENBLAS_NUM_THREADS=2 OMP_NUM_THREADS=2 OMP_THREAD_LIMIT=1 (caps num_threads clauses too)
# in ROUNDS interleaved rounds. Writes runs.csv and table.md here. Usage (repository root, after building
# deformbench): results/records/2026-11-26-cholmod-threads/run.sh [ROUNDS] [EDIT]
set -euo pipefail
rounds=${1:-3} edit=${2:-data/edits/armadillo_loop1_whole.edit}
here=$(cd "$(dirname "$0")" && pwd)
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)" > "$here/run.log"
echo "round,config,factorize_s,init_s" > "$here/runs.csv"
one() {  # config env...
  local c=$1; shift
  env -u OMP_NUM_THREADS -u OMP_WAIT_POLICY -u OMP_THREAD_LIMIT DEFORMBENCH_THREADS=2 "$@" \
    build/deformbench deform "$edit" --method tf --constraints soft --frames 1 --solver cholmod_supernodal \
    --out "$t/o.ply" --csv "$t/o.csv" > /dev/null
  /usr/bin/python3 -c 'import csv,sys; r=next(csv.DictReader(open(sys.argv[1]))); print(",".join([sys.argv[2], sys.argv[3], r["factorize_s"], r["init_s"]]))' \
    "$t/o.csv" "$r" "$c" >> "$here/runs.csv"
}
for ((r = 1; r <= rounds; r++)); do
  one t1 OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 DEFORMBENCH_THREADS=1
  one omp2 OPENBLAS_NUM_THREADS=2 OMP_NUM_THREADS=2
  one omp_unset OPENBLAS_NUM_THREADS=2
  one omp1 OPENBLAS_NUM_THREADS=2 OMP_NUM_THREADS=1
  one passive OPENBLAS_NUM_THREADS=2 OMP_NUM_THREADS=2 OMP_WAIT_POLICY=passive
  one limit1 OPENBLAS_NUM_THREADS=2 OMP_NUM_THREADS=2 OMP_THREAD_LIMIT=1
  echo "load after round $r: $(cut -d' ' -f1-3 /proc/loadavg)" >> "$here/run.log"
done
/usr/bin/python3 - "$here/runs.csv" > "$here/table.md" <<'PY'
import csv, statistics, sys, collections
rows = list(csv.DictReader(open(sys.argv[1])))
by = collections.defaultdict(list)
for r in rows: by[r["config"]].append(r)
base = {r["round"]: float(r["factorize_s"]) for r in by["omp2"]}
print("| config | factorize s: median (min-max) | init s: median | factorize / omp2's, per round: median (min-max) |")
print("|---|---|---|---|")
for c, rs in by.items():
    f = [float(r["factorize_s"]) for r in rs]; i = [float(r["init_s"]) for r in rs]
    q = [float(r["factorize_s"]) / base[r["round"]] for r in rs]
    print(f"| {c} | {statistics.median(f):.3f} ({min(f):.3f}-{max(f):.3f}) | {statistics.median(i):.3f} | "
          f"{statistics.median(q):.3f} ({min(q):.3f}-{max(q):.3f}) |")
PY
cat "$here/table.md"
