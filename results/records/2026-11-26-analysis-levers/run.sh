#!/usr/bin/env bash
# Issue 31 item 1 on the 2-core machine: the analysis phase (vertex ordering + multifrontal symbolic analysis),
# the ordering's CPU time and nnz(L) of the 26k and 104k armadillo TF edits under the metis (default) and ringnd
# orderings, for several builds of experiments/analysis.cpp in interleaved rounds: the first build is the
# baseline, each round runs every build once (the order rotates from round to round), each over both edits and
# both orderings; the load average is logged before every run. Writes LABEL.csv per build (the driver's rows,
# with provenance), load.log and table.md here.
# usage: results/records/2026-11-26-analysis-levers/run.sh ROUNDS LABEL=EXP_ANALYSIS [LABEL=EXP_ANALYSIS ...]
#        (from the repository root; the first: a build of main b33a526)
set -euo pipefail
rounds=$1; shift
labels=() bins=()
for a in "$@"; do labels+=("${a%%=*}"); bins+=("${a#*=}"); done
here=$(cd "$(dirname "$0")" && pwd)
export DEFORMBENCH_THREADS=2 OPENBLAS_NUM_THREADS=2
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
: > "$here/load.log"
n=${#bins[@]}
for ((r = 1; r <= rounds; r++)); do
  for ((k = 0; k < n; k++)); do
    i=$(((k + r) % n))
    echo "round $r ${labels[i]} load $(cut -d' ' -f1-3 /proc/loadavg) at $(date -u +%H:%M:%S)" | tee -a "$here/load.log"
    "${bins[i]}" --edit data/edits/armadillo_whole.edit --edit data/edits/armadillo_loop1_whole.edit --system tf \
      --orderings metis,ringnd --rounds 1 --csv "$t/${labels[i]}.$r.csv" > /dev/null
  done
done
echo "after: load $(cut -d' ' -f1-3 /proc/loadavg) at $(date -u +%H:%M:%S)" | tee -a "$here/load.log"
for b in "${labels[@]}"; do
  /usr/bin/python3 - "$t" "$b" "$rounds" > "$here/$b.csv" <<'PY'
import csv, sys
d, b, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
w = None
for r in range(1, n + 1):
    for row in csv.DictReader(open(f"{d}/{b}.{r}.csv")):
        row["round"] = str(r)
        if w is None:
            w = csv.DictWriter(sys.stdout, fieldnames=list(row)); w.writeheader()
        w.writerow(row)
PY
done
/usr/bin/python3 - "$here" "${labels[@]}" > "$here/table.md" <<'PY'
import csv, statistics, sys, collections
d, labels = sys.argv[1], sys.argv[2:]
cell = collections.defaultdict(dict)
for b in labels:
    for r in csv.DictReader(open(f"{d}/{b}.csv")):
        cell[(r["edit"], r["ordering"], b)][r["round"]] = r
def spread(v): return f"{statistics.median(v):.3f} ({min(v):.3f}-{max(v):.3f})"
print(f"| edit | ordering | build | analysis s: median (min-max) | ordering s | ordering CPU s | mf analysis s | nnz(L) | "
      f"analysis / {labels[0]}'s, per round | ordering CPU / {labels[0]}'s, per round | children's CPU s |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for e, o in dict.fromkeys((e, o) for e, o, _ in cell):
    for b in labels:
        rs, base = cell[(e, o, b)], cell[(e, o, labels[0])]
        v = lambda k: [float(x[k]) for x in rs.values()]
        ratio = lambda k: "" if b == labels[0] else spread([float(x[k]) / float(base[r][k]) for r, x in rs.items()])
        nnz = ", ".join(sorted({x["nnz_L"] for x in rs.values()}))
        print(f"| {e} | {o} | {b} | {spread(v('analysis_s'))} | {spread(v('order_s'))} | {spread(v('order_cpu_s'))} | "
              f"{spread(v('mf_analyze_s'))} | {nnz} | {ratio('analysis_s')} | {ratio('order_cpu_s')} | "
              f"{spread(v('order_children_cpu_s'))} |")
PY
cat "$here/table.md"
