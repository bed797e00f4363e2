#!/usr/bin/env bash
# What the deterministic multifrontal costs: the same edits with two builds, before (OLD) and after (NEW), in
# interleaved rounds (OLD, NEW, OLD, ...) at DEFORMBENCH_THREADS = OPENBLAS_NUM_THREADS = 2 on a box with nothing
# else running, one CSV row a run (the CLI's --csv row plus the build's label and the round).
# usage: run.sh ROUNDS OLD_DEFORMBENCH NEW_DEFORMBENCH > runs.csv     (from the repository root)
set -euo pipefail
rounds=$1 old=$2 new=$3
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
edits=(data/edits/armadillo_whole.edit data/edits/armadillo_loop1_whole.edit)
header=
for ((r = 1; r <= rounds; r++)); do
  for e in "${edits[@]}"; do
    for method in tf lap; do
      for label in old new; do
        bin=$old; [ $label = new ] && bin=$new
        DEFORMBENCH_THREADS=2 OPENBLAS_NUM_THREADS=2 "$bin" deform "$e" --method $method --constraints soft --frames 20 \
          --out "$t/o.ply" --csv "$t/o.csv" >/dev/null
        # Only the columns both builds write, in the old header's order.
        /usr/bin/python3 - "$t/o.csv" "$label" "$r" "$header" <<'PY'
import csv, sys
row = next(csv.DictReader(open(sys.argv[1])))
keys = ["mesh","edit","vertices","faces","handle","fixed","method","weights","constraints","build","backend","ordering","factor_storage","n","nnz","nnz_factor","build_s","analyze_s","factorize_s","init_s","drag","frame_mode","precompute_s","frames","frame_median_s","response_median_s","response_bytes","matrix_bytes","factor_bytes","peak_rss_bytes","ranks","peak_rss_rank_bytes","precision","refine_iterations","refine_residual","refine_correction","refine_tolerance","mixed_vs_double","git_sha","blas","blas_core","blas_coretype_env","blas_threads","build_threads","hardware_threads","cpu","compiler","timestamp"]
if sys.argv[4] == "":
    print(",".join(["label", "round"] + keys))
print(",".join([sys.argv[2], sys.argv[3]] + [row.get(k, "") for k in keys]))
PY
        header=1
      done
    done
  done
done
