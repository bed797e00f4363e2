#!/usr/bin/env bash
# One thread: the dissected METIS order postordered part by part (handing its tree to the symbolic analysis, NEW)
# against CHOLMOD's analysis of the whole graph (no tree, OLD: the rule before), in ROUNDS interleaved rounds
# (the order of the two builds alternating) of build/exp_analysis on the 104k and 416k armadillo TF edits at
# DEFORMBENCH_THREADS=1. Writes one_thread.csv (every row with the build's name) and appends its table to table.md.
# usage: results/records/2026-11-28-given-tree/one_thread.sh ROUNDS OLD/exp_analysis   (from the repository root)
set -euo pipefail
rounds=${1:?ROUNDS} old=${2:?OLD exp_analysis}
here=$(cd "$(dirname "$0")" && pwd)
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
export DEFORMBENCH_THREADS=1 OPENBLAS_NUM_THREADS=1
out="$here/one_thread.csv"; rm -f "$out"
for ((r = 1; r <= rounds; r++)); do
  if ((r % 2)); then order=(old new); else order=(new old); fi
  for b in "${order[@]}"; do
    bin=build/exp_analysis; [ "$b" = old ] && bin=$old
    echo "$(date -u +%H:%M:%S) load $(cut -d' ' -f1-3 /proc/loadavg): one thread, round $r $b" | tee -a "$here/run.log"
    "$bin" --edit data/edits/armadillo_loop1_whole.edit --edit data/edits/armadillo_loop2_whole.edit --system tf \
      --orderings metis --rounds 1 --csv "$t/one.csv" > /dev/null
    [ -s "$out" ] || { printf 'build_name,round_pair,'; head -1 "$t/one.csv"; } > "$out"
    tail -n +2 "$t/one.csv" | sed "s/^/$b,$r,/" >> "$out"
  done
done
/usr/bin/python3 - "$out" >> "$here/table.md" <<'PY'
import csv, collections, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
cells = collections.defaultdict(lambda: collections.defaultdict(list))
for r in rows:
    for col in ("order_s", "mf_analyze_s", "analysis_s"):
        cells[int(r["vertices"])][(r["build_name"], col)].append(float(r[col]))
def spread(v): return f"{statistics.median(v):.3f} ({min(v):.3f}-{max(v):.3f})"
print("\nOne thread (one_thread.sh): old = CHOLMOD's analysis of the whole graph postorders the order, no tree; "
      "new = the parts postordered one after the other, the tree handed on. Median (min-max) of the rounds.\n")
print("| edit (TF) | ordering s, old | ordering s, new | symbolic s, old | symbolic s, new | analysis s, old | analysis s, new | new / old analysis per round |")
print("|---|---|---|---|---|---|---|---|")
for v in sorted(cells):
    c = cells[v]
    ratio = ", ".join(f"{n / o:.2f}" for o, n in zip(c[("old", "analysis_s")], c[("new", "analysis_s")]))
    print(f"| {v // 1000}k | {spread(c[('old', 'order_s')])} | {spread(c[('new', 'order_s')])} | "
          f"{spread(c[('old', 'mf_analyze_s')])} | {spread(c[('new', 'mf_analyze_s')])} | "
          f"{spread(c[('old', 'analysis_s')])} | {spread(c[('new', 'analysis_s')])} | {ratio} |")
PY
tail -6 "$here/table.md"
