#!/usr/bin/env bash
# Issue 31 items 1 and 3, counted on any machine: per thread count T = 1 .. 64, the vertex ordering a run on T
# threads computes (METIS dissects one more level per doubling beyond two) and its fill, and what the multifrontal
# factorization's plan gives its two phases (subtree groups on single-threaded BLAS; the serial top phase on the
# BLAS's threads): the 26k, 104k and 416k armadillo edits, TF and LAP (experiments/tree_parallelism.cpp).
# Writes tree_parallelism.csv and table.md here.
# usage: results/records/2026-11-26-tree-parallelism/run.sh   (from the repository root, after building
#        exp_tree_parallelism in build/; the 416k edit's mesh is data/generated/armadillo_loop2.off)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
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
