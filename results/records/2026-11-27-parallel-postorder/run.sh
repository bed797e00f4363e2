#!/usr/bin/env bash
# Issue 31, item 1 (the analysis on the threads): the vertex ordering's METIS order postordered part by part on the
# worker threads (NEW) against CHOLMOD's postordering analysis of the whole graph (BASE), in interleaved rounds (the
# order of the two builds alternates): the analysis phase (build/exp_analysis: ordering = 2-ring pattern + METIS +
# postorder; then the multifrontal symbolic analysis) of the 26k, 104k and 416k armadillo TF edits under metis, at
# 1 and 2 threads. Writes analysis.csv (every row, with provenance and the build's name), table.md and run.log here.
# usage: results/records/2026-11-27-parallel-postorder/run.sh ROUNDS BASE_BUILD NEW_BUILD   (from the repository
#        root; each BUILD a build directory holding exp_analysis)
set -euo pipefail
rounds=${1:?ROUNDS} base=${2:?BASE_BUILD} new=${3:?NEW_BUILD}
here=$(cd "$(dirname "$0")" && pwd)
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
log() { echo "$(date -u +%H:%M:%S) load $(cut -d' ' -f1-3 /proc/loadavg): $*" | tee -a "$here/run.log"; }
: > "$here/run.log"
rm -f "$t/all.csv"
for ((r = 1; r <= rounds; r++)); do
  if ((r % 2)); then order=(base new); else order=(new base); fi
  for b in "${order[@]}"; do
    dir=$base; [ "$b" = new ] && dir=$new
    for threads in 1 2; do
      log "round $r $b $threads threads"
      DEFORMBENCH_THREADS=$threads OPENBLAS_NUM_THREADS=$threads "$dir/exp_analysis" \
        --edit data/edits/armadillo_whole.edit --edit data/edits/armadillo_loop1_whole.edit \
        --edit data/edits/armadillo_loop2_whole.edit --system tf --orderings metis --rounds 1 --csv "$t/one.csv" > /dev/null
      /usr/bin/python3 - "$b" "$r" "$t/one.csv" "$t/all.csv" <<'PY'
import csv, os, sys
name, rnd, src, out = sys.argv[1:]
rows = list(csv.DictReader(open(src)))
for row in rows: row["round"] = rnd; row["build_name"] = name
new = not os.path.exists(out)
with open(out, "a", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
    if new: w.writeheader()
    w.writerows(rows)
PY
    done
  done
done
log done
cp "$t/all.csv" "$here/analysis.csv"
/usr/bin/python3 - "$here/analysis.csv" > "$here/table.md" <<'PY'
import csv, collections, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
def spread(v): return f"{statistics.median(v):.3f} ({min(v):.3f}-{max(v):.3f})"
cells = collections.defaultdict(lambda: collections.defaultdict(list))
nnz = collections.defaultdict(set)
for r in rows:
    k = (int(r["vertices"]), int(r["threads"]))
    for col in ("order_s", "mf_analyze_s", "analysis_s"):
        cells[k][(r["build_name"], col)].append(float(r[col]))
    nnz[k].add((r["build_name"], r["nnz_L"]))
print("| edit (TF) | threads | ordering s, base | ordering s, new | new / base per round | analysis s, base | analysis s, new | nnz(L) the same |")
print("|---|---|---|---|---|---|---|---|")
for k in sorted(cells):
    c = cells[k]
    ratio = [n / b for b, n in zip(c[("base", "order_s")], c[("new", "order_s")])]
    same = len({v for _, v in nnz[k]}) == 1
    print(f"| {k[0] // 1000}k | {k[1]} | {spread(c[('base', 'order_s')])} | {spread(c[('new', 'order_s')])} | "
          f"{', '.join(f'{x:.2f}' for x in ratio)} | {spread(c[('base', 'analysis_s')])} | {spread(c[('new', 'analysis_s')])} | {'yes' if same else 'no'} |")
PY
cat "$here/table.md"
