#!/usr/bin/env bash
# Issue 31, item 1: the dissected METIS ordering's elimination tree and column counts handed to the multifrontal
# analysis (e92e762), on this 2-core machine. Two parts, each in ROUNDS interleaved rounds at 2 threads:
#  1. build/exp_analysis on the 26k, 104k and 416k armadillo TF edits: per round the symbolic analysis from the
#     ordering's tree (mf_analyze_s, what the deformation runs) and from CHOLMOD's own pass over the same ordered
#     graph (mf_own_tree_s), the two timed one after the other, their order alternating (analysis_2.csv);
#  2. the 104k TF deformation's init (one frame) by BASE (a build before e92e762) and by build/deformbench, their
#     order alternating (init_2.csv: each deform row with the build's name), and whether their deformed meshes
#     are the same bytes.
# The machine's dgemm and memory rates at 2 threads before and after (rates.csv). Writes table.md and run.log here.
# usage: results/records/2026-11-28-given-tree/run.sh ROUNDS BASE/deformbench   (from the repository root, after
#        cmake --build build --target exp_analysis deformbench exp_machine_rates)
set -euo pipefail
rounds=${1:?ROUNDS} base=${2:?BASE deformbench}
here=$(cd "$(dirname "$0")" && pwd)
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
log() { echo "$(date -u +%H:%M:%S) load $(cut -d' ' -f1-3 /proc/loadavg): $*" | tee -a "$here/run.log"; }
export DEFORMBENCH_THREADS=2 OPENBLAS_NUM_THREADS=2
: > "$here/run.log"
rates() {
  build/exp_machine_rates --csv "$t/r.csv" > /dev/null
  [ -s "$here/rates.csv" ] || { printf 'phase,'; head -1 "$t/r.csv"; } > "$here/rates.csv"
  tail -n +2 "$t/r.csv" | sed "s/^/$1,/" >> "$here/rates.csv"
}
rm -f "$here/rates.csv"; rates before
log "exp_analysis, $rounds rounds"
build/exp_analysis --edit data/edits/armadillo_whole.edit --edit data/edits/armadillo_loop1_whole.edit \
  --edit data/edits/armadillo_loop2_whole.edit --system tf --orderings metis --rounds "$rounds" \
  --csv "$here/analysis_2.csv" > /dev/null
rm -f "$here/init_2.csv"
for ((r = 1; r <= rounds; r++)); do
  if ((r % 2)); then order=(base new); else order=(new base); fi
  for b in "${order[@]}"; do
    bin=build/deformbench; [ "$b" = base ] && bin=$base
    log "round $r $b init"
    "$bin" deform data/edits/armadillo_loop1_whole.edit --method tf --constraints soft --frames 1 \
      --out "$t/$b.ply" --csv "$t/one.csv" > /dev/null
    [ -s "$here/init_2.csv" ] || { printf 'build_name,round,'; head -1 "$t/one.csv"; } > "$here/init_2.csv"
    tail -n +2 "$t/one.csv" | sed "s/^/$b,$r,/" >> "$here/init_2.csv"
  done
  cmp -s "$t/base.ply" "$t/new.ply" && log "round $r: the same deformed mesh" || log "round $r: the meshes differ"
done
rates after
log done
/usr/bin/python3 - "$here" > "$here/table.md" <<'PY'
import csv, collections, statistics, sys
here = sys.argv[1]
def spread(v): return f"{statistics.median(v):.3f} ({min(v):.3f}-{max(v):.3f})"
rows = list(csv.DictReader(open(f"{here}/analysis_2.csv")))
by = collections.defaultdict(list)
for r in rows: by[int(r["vertices"])].append(r)
print("Symbolic analysis of the ordered TF system, 2 threads: median (min-max) of the rounds; both in every round.\n")
print("| edit (TF) | rounds | tree given | from the ordering's tree s | from CHOLMOD's own pass s | saved per round s | ordering s | nnz(L) |")
print("|---|---|---|---|---|---|---|---|")
for v in sorted(by):
    rs = by[v]
    given = [float(r["mf_analyze_s"]) for r in rs]
    own = [float(r["mf_own_tree_s"]) for r in rs]
    saved = [o - g for g, o in zip(given, own)]
    print(f"| {v // 1000}k | {len(rs)} | {'all' if all(r['tree_given'] == '1' for r in rs) else 'not all'} | "
          f"{spread(given)} | {spread(own)} | {spread(saved)} | {spread([float(r['order_s']) for r in rs])} | "
          f"{rs[0]['nnz_L']} |")
init = list(csv.DictReader(open(f"{here}/init_2.csv")))
cells = collections.defaultdict(lambda: collections.defaultdict(list))
for r in init:
    for col in ("init_s", "analyze_s", "factorize_s", "build_s"):
        cells[col][r["build_name"]].append(float(r[col]))
print("\n104k TF deformation, 2 threads, base and new alternating: median (min-max); new / base per round.\n")
print("| phase | base s | new s | new / base per round |")
print("|---|---|---|---|")
for col, c in cells.items():
    ratio = ", ".join(f"{n / b:.2f}" for b, n in zip(c["base"], c["new"]))
    print(f"| {col} | {spread(c['base'])} | {spread(c['new'])} | {ratio} |")
rates = list(csv.DictReader(open(f"{here}/rates.csv")))
print("\nMachine rates at 2 threads: " + "; ".join(
    f"{r['phase']}: dgemm {float(r['blas_dgemm_flops']) / 1e9:.0f} GFlop/s, memory read "
    f"{float(r['memory_read_bytes_per_s']) / 1e9:.1f} GB/s" for r in rates))
PY
cat "$here/table.md"
