#!/usr/bin/env bash
# The factorization's subtree phase split into K times as many groups as threads, claimed by the threads as they
# come (over_decomposition.patch: DBK=K; run_tasks with at most `threads` threads), on the 2-core development
# machine, quiet and beside a busy loop on one core: the 104k TF init at 2 threads, K = 1, 2, 4 alternating.
#   two_core.sh BUILD_WITH_PATCH ROUNDS   (from the repository root; prints one line per run)
set -euo pipefail
B=${1:?build dir with over_decomposition.patch}; R=${2:-3}
runs() {
  for r in $(seq "$R"); do for k in 1 2 4; do
    DBT=1 DBK=$k DEFORMBENCH_THREADS=2 OPENBLAS_NUM_THREADS=2 "$B/deformbench" deform data/edits/armadillo_loop1_whole.edit \
      --method tf --constraints soft --frames 1 --solver multifrontal --out /tmp/od.$$.ply --csv /tmp/od.$$.csv 2> /tmp/od.$$.err > /dev/null
    echo "$1 r$r k$k $(grep -c '^group' /tmp/od.$$.err) groups, $(grep '^subtrees' /tmp/od.$$.err)," \
      "factor_top_flops,factorize_s,factorize_top_s,init_s: $(cut -d, -f21,25-27 /tmp/od.$$.csv | tail -1)"
  done; done
}
trap 'rm -f /tmp/od.$$.*; [ -z "${busy:-}" ] || kill "$busy" 2>/dev/null' EXIT
runs quiet
sh -c 'while :; do :; done' & busy=$!
runs busy
