#!/usr/bin/env bash
# Issue 31, item 3: the factorization's independent top subtrees at once, each on a team of its own
# (solvers/multifrontal/top_phase.h), against the top supernodes one after another on one team (BASE, a build before
# it), on this machine. ROUNDS interleaved rounds: the 104k TF deformation (one frame) at DEFORMBENCH_THREADS = T for
# T in THREADS (default "16 8 2"), BASE and build/deformbench alternating, each run right after a process that wrote
# and freed 2 GB (the memory state of results/records/2026-11-27-fresh-memory); whether their meshes are the same
# bytes. The thread count fixes the plan (its top set); the teams are no larger than the cores (on 2 cores the top
# phase runs on at most 2 threads whatever T is), so at T = 16 and 8 here the top's branches run on one thread each
# against the base's team of two, and at T = 2, whose top is one chain, both run the same way: the control.
# EDIT (default data/edits/armadillo_loop1_whole.edit) takes another edit. Writes deform.csv (each deform row tagged
# with binary, round, threads), rates.csv (dgemm and memory rates at 2 threads before and after), table.md and
# run.log in OUT (default: here).
# usage: results/records/2026-11-28-top-branches/run.sh ROUNDS BASE/deformbench   (from the repository root, after
#        cmake --build build --target deformbench exp_machine_rates)
set -euo pipefail
rounds=${1:?ROUNDS} base=${2:?BASE deformbench}
here=${OUT:-$(cd "$(dirname "$0")" && pwd)}
mkdir -p "$here"
threads=${THREADS:-16 8 2} edit=${EDIT:-data/edits/armadillo_loop1_whole.edit}
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
log() { echo "$(date -u +%H:%M:%S) load $(cut -d' ' -f1-3 /proc/loadavg): $*" | tee -a "$here/run.log"; }
: > "$here/run.log"
rm -f "$here/rates.csv" "$here/deform.csv"
rates() {
  DEFORMBENCH_THREADS=2 OPENBLAS_NUM_THREADS=2 build/exp_machine_rates --csv "$t/r.csv" > /dev/null
  scripts/append_rows.py "$t/r.csv" "$here/rates.csv" phase="$1"
}
rates before
for ((r = 1; r <= rounds; r++)); do
  for T in $threads; do
    if ((r % 2)); then order=(base new); else order=(new base); fi
    for b in "${order[@]}"; do
      bin=build/deformbench; [ "$b" = base ] && bin=$base
      DEFORMBENCH_THREADS=2 OPENBLAS_NUM_THREADS=2 build/exp_machine_rates --gemm-size 64 --first-touch-mb 2048 \
        > /dev/null
      log "round $r threads $T $b"
      DEFORMBENCH_THREADS=$T OPENBLAS_NUM_THREADS=$T "$bin" deform "$edit" --method tf \
        --constraints soft --frames 1 --out "$t/$b.ply" --csv "$t/one.csv" > /dev/null
      scripts/append_rows.py "$t/one.csv" "$here/deform.csv" binary="$b" round="$r" threads="$T"
    done
    cmp -s "$t/base.ply" "$t/new.ply" && log "round $r threads $T: the same deformed mesh" ||
      log "round $r threads $T: the meshes differ"
  done
done
rates after
log done
/usr/bin/python3 - "$here" > "$here/table.md" <<'PY'
import collections, csv, statistics, sys
here = sys.argv[1]
def spread(v): return f"{statistics.median(v):.3f} ({min(v):.3f}-{max(v):.3f})"
rows = list(csv.DictReader(open(f"{here}/deform.csv")))
cell = collections.defaultdict(lambda: collections.defaultdict(dict))
for r in rows:
    cell[int(r["threads"])][r["binary"]][int(r["round"])] = r
print(f"{rows[0]['vertices']}-vertex TF deformation, base and new alternating: median (min-max) over the rounds; new / base per round.\n")
print("| T | top supernodes' GFlop | phase | base s | new s | new / base per round |")
print("|---|---|---|---|---|---|")
for T in sorted(cell, reverse=True):
    b, n = cell[T]["base"], cell[T]["new"]
    rounds = sorted(set(b) & set(n))
    for col in ("factorize_top_s", "factorize_s", "init_s"):
        bv = [float(b[k][col]) for k in rounds]
        nv = [float(n[k][col]) for k in rounds]
        ratio = ", ".join(f"{y / x:.2f}" for x, y in zip(bv, nv))
        print(f"| {T} | {float(b[rounds[0]]['factor_top_flops']) / 1e9:.1f} | {col} | {spread(bv)} | {spread(nv)} | {ratio} |")
rates = list(csv.DictReader(open(f"{here}/rates.csv")))
print("\nMachine rates at 2 threads: " + "; ".join(
    f"{r['phase']}: dgemm {float(r['blas_dgemm_flops']) / 1e9:.0f} GFlop/s, memory read "
    f"{float(r['memory_read_bytes_per_s']) / 1e9:.1f} GB/s" for r in rates))
PY
cat "$here/table.md"
