#!/usr/bin/env bash
# nnz(L) and flops of the TF edits (26k, 104k, 416k) under the dissected METIS ordering at L = 1..4 levels (its
# levels follow DEFORMBENCH_THREADS = 2^L) against the ring dissection split on the 1-ring graph at the same L
# levels, METIS on the 2-ring graphs of the parts below (first split at ufactor 20, as the METIS path's).
# Needs build/exp_analysis built with ring_levels.patch applied (it adds DB_RING_LEVELS and DB_RING_UF); the
# fill does not depend on the machine, the order_cpu columns do. From the repository root:
#   results/records/2026-11-27-one-ring-splits/tuning/fill.sh
set -euo pipefail
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
for e in armadillo_whole armadillo_loop1_whole armadillo_loop2_whole; do
for L in 1 2 3 4; do T=$((1<<L)); 
  DEFORMBENCH_THREADS=$T OPENBLAS_NUM_THREADS=1 ./build/exp_analysis --edit data/edits/$e.edit --system tf --orderings metis --rounds 1 --csv $t/m.csv >/dev/null 2>&1
  DB_RING_LEVELS=$L DB_RING_UF=20 DEFORMBENCH_THREADS=$T OPENBLAS_NUM_THREADS=1 ./build/exp_analysis --edit data/edits/$e.edit --system tf --orderings ringnd --rounds 1 --csv $t/r.csv >/dev/null 2>&1
  /usr/bin/python3 - $e $L "$t/m.csv" "$t/r.csv" <<'P'
import csv,sys
m=list(csv.DictReader(open(sys.argv[3])))[0]; r=list(csv.DictReader(open(sys.argv[4])))[0]
print(sys.argv[1], 'L', sys.argv[2], 'metis nnz', m['nnz_L'], 'gflop %.2f'%float(m['gflop']), 'order_cpu %.3f'%float(m['order_cpu_s']), '| ring nnz', r['nnz_L'], 'gflop %.2f'%float(r['gflop']), 'order_cpu %.3f'%float(r['order_cpu_s']), '| nnz ratio %.4f flop ratio %.4f'%(int(r['nnz_L'])/int(m['nnz_L']), float(r['gflop'])/float(m['gflop'])))
P
done; done
