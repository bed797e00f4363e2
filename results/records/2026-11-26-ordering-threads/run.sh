#!/usr/bin/env bash
# Issue 31 item 1 on 2 cores: the METIS orderings' two sides on two threads (METIS's draws kept per thread,
# solvers/ordering/metis_random.h) against the forked child process they replace, in interleaved rounds (the
# order of the two builds alternates): (a) the analysis phase (ordering + multifrontal symbolic analysis),
# nnz(L), of the 26k and 104k armadillo TF edits under metis and ringnd and the 104k LAP edit under metis
# (build/exp_analysis); (b) the 104k TF deformation's init split (build, analyze, factorize) with the multifrontal
# backend, one frame, a fresh process per run. Writes analysis_{base,new}.csv, init.csv, table.md and run.log here.
# usage: results/records/2026-11-26-ordering-threads/run.sh ROUNDS BASE_BUILD NEW_BUILD   (from the repository
#        root; each BUILD a build directory holding exp_analysis and deformbench)
set -euo pipefail
rounds=${1:?ROUNDS} base=${2:?BASE_BUILD} new=${3:?NEW_BUILD}
here=$(cd "$(dirname "$0")" && pwd)
export DEFORMBENCH_THREADS=2 OPENBLAS_NUM_THREADS=2
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
log() { echo "$(date -u +%H:%M:%S) load $(cut -d' ' -f1-3 /proc/loadavg): $*" | tee -a "$here/run.log"; }
: > "$here/run.log"
echo "build,round,edit,method,build_s,analyze_s,factorize_s,init_s,nnz_factor" > "$here/init.csv"
analysis() {  # NAME BUILD ROUND
  "$2/exp_analysis" --edit data/edits/armadillo_whole.edit --edit data/edits/armadillo_loop1_whole.edit --system tf \
    --orderings metis,ringnd --rounds 1 --csv "$t/tf.csv" > /dev/null
  "$2/exp_analysis" --edit data/edits/armadillo_loop1_whole.edit --system lap --orderings metis --rounds 1 \
    --csv "$t/lap.csv" > /dev/null
  /usr/bin/python3 - "$1" "$3" "$here/analysis_$1.csv" "$t/tf.csv" "$t/lap.csv" <<'PY'
import csv, os, sys
name, rnd, out, *ins = sys.argv[1:]
rows = [r for f in ins for r in csv.DictReader(open(f))]
for r in rows: r["round"] = rnd; r["build_name"] = name
new = not os.path.exists(out)
with open(out, "a", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
    if new: w.writeheader()
    w.writerows(rows)
PY
}
init() {  # NAME BUILD ROUND
  "$2/deformbench" deform data/edits/armadillo_loop1_whole.edit --method tf --constraints soft --frames 1 \
    --solver multifrontal --out "$t/o.ply" --csv "$t/o.csv" > /dev/null
  /usr/bin/python3 -c 'import csv,sys; r=next(csv.DictReader(open(sys.argv[4]))); print(",".join(sys.argv[1:4] + [r[k] for k in ("build_s","analyze_s","factorize_s","init_s","nnz_factor")]))' \
    "$1" "$3" "armadillo_loop1_whole,tf" "$t/o.csv" >> "$here/init.csv"
}
rm -f "$here/analysis_base.csv" "$here/analysis_new.csv"
for ((r = 1; r <= rounds; r++)); do
  if ((r % 2)); then order=(base new); else order=(new base); fi
  for b in "${order[@]}"; do
    dir=$base; [ "$b" = new ] && dir=$new
    log "round $r $b"
    analysis "$b" "$dir" "$r"
    init "$b" "$dir" "$r"
  done
done
log done
/usr/bin/python3 - "$here" > "$here/table.md" <<'PY'
import csv, collections, statistics, sys
d = sys.argv[1]
def spread(v): return f"{statistics.median(v):.3f} ({min(v):.3f}-{max(v):.3f})"
cells = collections.defaultdict(lambda: collections.defaultdict(dict))
nnz = {}
for b in ("base", "new"):
    for r in csv.DictReader(open(f"{d}/analysis_{b}.csv")):
        k = (r["edit"], r["system"], r["ordering"])
        cells[k][r["round"]][b] = (float(r["analysis_s"]), float(r["order_cpu_s"]) + float(r["order_children_cpu_s"]))
        nnz.setdefault(k, {})[b] = r["nnz_L"]
print("| edit | system | ordering | analysis s, fork (base) | analysis s, threads (new) | new / base, per round | ordering CPU s (all processes), base | new | nnz(L) base / new |")
print("|---|---|---|---|---|---|---|---|---|")
for k, rounds in cells.items():
    rs = [v for v in rounds.values() if len(v) == 2]
    a = [v["base"][0] for v in rs]; b = [v["new"][0] for v in rs]
    ca = [v["base"][1] for v in rs]; cb = [v["new"][1] for v in rs]
    print(f"| {k[0]} | {k[1]} | {k[2]} | {spread(a)} | {spread(b)} | {spread([y / x for x, y in zip(a, b)])} | {spread(ca)} | {spread(cb)} | {nnz[k]['base']} / {nnz[k]['new']} |")
print()
ini = collections.defaultdict(dict)
for r in csv.DictReader(open(f"{d}/init.csv")): ini[r["round"]][r["build"]] = r
print("| 104k TF, multifrontal | base (fork) | new (threads) | new / base, per round |")
print("|---|---|---|---|")
for col in ("build_s", "analyze_s", "factorize_s", "init_s"):
    rs = [v for v in ini.values() if len(v) == 2]
    a = [float(v["base"][col]) for v in rs]; b = [float(v["new"][col]) for v in rs]
    print(f"| {col} | {spread(a)} | {spread(b)} | {spread([y / x for x, y in zip(a, b)])} |")
print(f"\nnnz_factor base / new: {rs[0]['base']['nnz_factor']} / {rs[0]['new']['nnz_factor']}")
PY
cat "$here/table.md"
