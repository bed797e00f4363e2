#!/usr/bin/env bash
# The TF factor's fill per thread count of the vertex ordering a run on T threads computes (METIS dissects one
# level more per doubling of the threads beyond two; experiments/tree_parallelism.cpp), for builds given as
# LABEL=PATH of exp_tree_parallelism: the 26k, 104k and 416k armadillo edits at T = 1, 4, 8, 16, 32, 64 (2 orders
# as 1). Writes fill_LABEL.csv per build (its rows with provenance) and fill.md (nnz(L) and GFlop per build, and
# each build's ratio to the first) here; a bare LABEL reuses the fill_LABEL.csv already here. Counts, not times:
# the same on any machine.
# usage: results/records/2026-11-27-guided-splits/fill.sh LABEL[=EXP_TREE_PARALLELISM] ...   (from the repository
#        root; data/generated/armadillo_loop2.off as in ../2026-11-27-init-floor)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
labels=()
for arg in "$@"; do
  label=${arg%%=*} exe=${arg#*=}
  labels+=("$label")
  [ "$arg" != "$label" ] || continue
  "$exe" --edit data/edits/armadillo_whole.edit --edit data/edits/armadillo_loop1_whole.edit \
    --edit data/edits/armadillo_loop2_whole.edit --system tf --threads 1,4,8,16,32,64 \
    --csv "$here/fill_$label.csv" >/dev/null
done
/usr/bin/python3 - "$here" "${labels[@]}" > "$here/fill.md" <<'PY'
import csv, sys
here, labels = sys.argv[1], sys.argv[2:]
rows = {l: list(csv.DictReader(open(f"{here}/fill_{l}.csv"))) for l in labels}
def key(r): return (int(r["vertices"]), int(r["threads"]))
table = {l: {key(r): r for r in rs} for l, rs in rows.items()}
first = labels[0]
print("| vertices | T | " + " | ".join(f"{l}: nnz(L), GFlop" for l in labels) + " | "
      + " | ".join(f"{l} / {first}: nnz, flops" for l in labels[1:]) + " |")
print("|---|---|" + "---|" * (2 * len(labels) - 1))
for k in sorted(table[first]):
    cells = [table[l][k] for l in labels]
    v = [f"{int(c['nnz_L'])}, {float(c['flops']) / 1e9:.2f}" for c in cells]
    b = cells[0]
    ratio = [f"{int(c['nnz_L']) / int(b['nnz_L']):.4f}, {float(c['flops']) / float(b['flops']):.4f}"
             for c in cells[1:]]
    print(f"| {k[0]} | {k[1]} | " + " | ".join(v + ratio) + " |")
print()
print("Builds: " + ", ".join(f"{l} = git {rows[l][0]['git_sha'][:7]}" for l in labels) + ".")
PY
cat "$here/fill.md"
