#!/usr/bin/env bash
# Issue 31 items 1 and 3, counted on any machine: per thread count T = 1 .. 64, the vertex ordering a run on T
# threads computes (METIS dissects one more level per doubling beyond two) and its fill, and what the multifrontal
# factorization's plan gives its two phases (subtree groups on single-threaded BLAS; the serial top phase on the
# BLAS's threads): the 26k, 104k and 416k armadillo edits, TF and LAP (experiments/tree_parallelism.cpp).
# Writes tree_parallelism.csv and table.md here. Part `measure` (on a quiet machine): the 104k TF factorization
# on this machine's threads, 3 runs, its top phase timed (factorize_top_s) beside the whole: measured.csv.
# usage: results/records/2026-11-26-tree-parallelism/run.sh [counts|measure]   (from the repository root, after
#        building exp_tree_parallelism and deformbench in build/; the 416k edit's mesh is
#        data/generated/armadillo_loop2.off)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
if [ "${1:-counts}" = measure ]; then
  t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
  cols="factorize_s factorize_top_s factor_flops factor_top_flops init_s"
  echo "run,threads,load,${cols// /,}" > "$here/measured.csv"
  for r in 1 2 3; do
    build/deformbench deform data/edits/armadillo_loop1_whole.edit --method tf --constraints soft --frames 1 \
      --solver multifrontal --out "$t/o.ply" --csv "$t/o.csv" > /dev/null
    /usr/bin/python3 -c 'import csv,sys; r=next(csv.DictReader(open(sys.argv[1]))); print(",".join(sys.argv[3:] + [r[k] for k in sys.argv[2].split()]))' \
      "$t/o.csv" "$cols" "$r" "${DEFORMBENCH_THREADS:-default}" "$(cut -d' ' -f1 /proc/loadavg)" >> "$here/measured.csv"
  done
  cat "$here/measured.csv"
  exit 0
fi
build/exp_tree_parallelism --edit data/edits/armadillo_whole.edit --edit data/edits/armadillo_loop1_whole.edit \
  --edit data/edits/armadillo_loop2_whole.edit --threads 1,2,4,8,16,32,64 --csv "$here/tree_parallelism.csv"
/usr/bin/python3 - "$here/tree_parallelism.csv" > "$here/table.md" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
first = {}
for r in rows:
    first.setdefault((r["edit"], r["system"]), r)
print("| vertices | system | T | nnz(L) / 1 thread's | flops / 1 thread's | largest group / mean | top supernodes | top share of flops | top's costliest chain / top | top fronts' rows: median, largest | speedup bound: top on 1 core | top at T x 1 core |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|")
for r in rows:
    f = first[(r["edit"], r["system"])]
    top = float(r["top_flops"])
    chain = f"{float(r['top_path_flops']) / top:.2f}" if top > 0 else "-"
    balance = float(r["group_flops_max"]) / float(r["group_flops_mean"])
    print(f"| {r['vertices']} | {r['system']} | {r['threads']} | {int(r['nnz_L']) / int(f['nnz_L']):.4f} | "
          f"{float(r['flops']) / float(f['flops']):.4f} | {balance:.2f} | {r['top_supernodes']} | {float(r['top_share']):.2f} | "
          f"{chain} | {r['top_rows_median']}, {r['top_rows_max']} | {float(r['bound_top_serial']):.2f} | {float(r['bound_top_ideal']):.2f} |")
PY
cat "$here/table.md"
