#!/usr/bin/env bash
# Issue 31 items 1 and 2 on the 2-core machine: (a) the analysis phase (vertex ordering + multifrontal symbolic
# analysis) and nnz(L) of the 26k and 104k armadillo edits, TF and LAP, under the vertex orderings metis (the TF
# default), ringnd (the 1-ring dissection) and amd (the LAP default), in interleaved rounds (experiments/analysis.cpp);
# (b) the full-frame median at 1 and 2 threads, paired in each round (the solves' thread choice by work);
# (c) the 104k TF init (build + analyze + factorize) of the multifrontal backend against CHOLMOD supernodal, paired
# in each round (the issue's 2-core target: init <= 0.6x CHOLMOD's in the same run).
# Writes analysis_{tf,lap}.csv, frames.csv, init.csv and table.md here. A copy of 2026-11-26-analysis-2core's script
# with part (c) added, run on a quiet machine.
# usage: results/records/2026-11-26-analysis-2core-quiet/run.sh ROUNDS [analysis|frames|init]   (from the repository root,
#        after building exp_analysis and deformbench in build/; both parts by default). RECORD_DIR=DIR writes
#        the files into DIR instead of beside this script (2026-11-26-analysis-levers/quiet does).
set -euo pipefail
rounds=${1:-3} part=${2:-both}
here=${RECORD_DIR:-$(cd "$(dirname "$0")" && pwd)}
edits=(--edit data/edits/armadillo_whole.edit --edit data/edits/armadillo_loop1_whole.edit)
export DEFORMBENCH_THREADS=2 OPENBLAS_NUM_THREADS=2
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
if [ "$part" = both ] || [ "$part" = analysis ]; then
build/exp_analysis "${edits[@]}" --system tf --orderings metis,ringnd --rounds "$rounds" --csv "$here/analysis_tf.csv"
build/exp_analysis "${edits[@]}" --system lap --orderings amd,metis,ringnd --rounds "$rounds" --csv "$here/analysis_lap.csv"
echo "load after the analysis rounds: $(cut -d' ' -f1-3 /proc/loadavg)"
fi

t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
frame_ms() {  # the full-frame median (ms) of one run: THREADS ARGS...
  local th=$1; shift
  DEFORMBENCH_THREADS=$th OPENBLAS_NUM_THREADS=$th build/deformbench deform "$@" --out "$t/o.ply" --csv "$t/o.csv" >/dev/null
  /usr/bin/python3 -c 'import csv,sys; r=next(csv.DictReader(open(sys.argv[1]))); print("%.4f" % (1e3*float(r["frame_s"])))' "$t/o.csv"
}
if [ "$part" = both ] || [ "$part" = frames ]; then
echo "edit,method,round,threads,frame_median_ms" > "$here/frames.csv"
for ((r = 1; r <= rounds; r++)); do
  for e in data/edits/armadillo_whole.edit data/edits/armadillo_loop1_whole.edit; do
    for method in tf lap; do
      args=("$e" --method "$method" --constraints soft --frames 10)
      for th in 1 2; do echo "$(basename "$e" .edit),$method,$r,$th,$(frame_ms "$th" "${args[@]}")" >> "$here/frames.csv"; done
    done
  done
done
echo "load after the frame rounds: $(cut -d' ' -f1-3 /proc/loadavg)"
fi

init_s() {  # init seconds of one run (build + analyze + factorize): ARGS...
  build/deformbench deform "$@" --out "$t/o.ply" --csv "$t/o.csv" >/dev/null
  /usr/bin/python3 -c 'import csv,sys; r=next(csv.DictReader(open(sys.argv[1]))); print(r["init_s"])' "$t/o.csv"
}
if [ "$part" = both ] || [ "$part" = init ]; then
echo "edit,method,round,backend,init_s" > "$here/init.csv"
for ((r = 1; r <= rounds; r++)); do
  for b in multifrontal cholmod_supernodal; do
    e=data/edits/armadillo_loop1_whole.edit
    echo "$(basename "$e" .edit),tf,$r,$b,$(init_s "$e" --method tf --constraints soft --frames 1 --solver "$b")" >> "$here/init.csv"
  done
done
echo "load after the init rounds: $(cut -d' ' -f1-3 /proc/loadavg)"
fi

/usr/bin/python3 - "$here" > "$here/table.md" <<'PY'
import csv, statistics, sys, collections
d = sys.argv[1]
rows = list(csv.DictReader(open(f"{d}/analysis_tf.csv"))) + list(csv.DictReader(open(f"{d}/analysis_lap.csv")))
cell = collections.defaultdict(list)
for r in rows: cell[(r["edit"], r["system"], r["ordering"])].append(r)
def spread(v): return f"{statistics.median(v):.3f} ({min(v):.3f}-{max(v):.3f})"
print("| edit | system | ordering | analysis s: median (min-max) | ordering CPU s | mf analysis s | nnz(L) | GFlop | analysis / first ordering's, per round: median (min-max) |")
print("|---|---|---|---|---|---|---|---|---|")
for (e, s, o), rs in cell.items():
    ref = cell[(e, s, "metis" if s == "tf" else "amd")]
    base = {r["round"]: float(r["analysis_s"]) for r in ref}
    ratio = [float(r["analysis_s"]) / base[r["round"]] for r in rs]
    print(f"| {e} | {s} | {o} | {spread([float(r['analysis_s']) for r in rs])} | {spread([float(r['order_cpu_s']) for r in rs])} | "
          f"{spread([float(r['mf_analyze_s']) for r in rs])} | {rs[0]['nnz_L']} | {float(rs[0]['gflop']):.2f} | {spread(ratio)} |")
print()
fr = collections.defaultdict(dict)
for r in csv.DictReader(open(f"{d}/frames.csv")): fr[(r["edit"], r["method"])].setdefault(r["round"], {})[r["threads"]] = float(r["frame_median_ms"])
print("| edit | method | frame ms, 1 thread | frame ms, 2 threads | 2 threads / 1 thread, per round: median (min-max) |")
print("|---|---|---|---|---|")
for (e, m), rounds in fr.items():
    one = [v["1"] for v in rounds.values()]; two = [v["2"] for v in rounds.values()]
    print(f"| {e} | {m} | {spread(one)} | {spread(two)} | {spread([b / a for a, b in zip(one, two)])} |")
print()
ini = collections.defaultdict(dict)
for r in csv.DictReader(open(f"{d}/init.csv")): ini[r["round"]][r["backend"]] = float(r["init_s"])
mf = [v["multifrontal"] for v in ini.values()]; ch = [v["cholmod_supernodal"] for v in ini.values()]
print("| edit | init s, multifrontal | init s, cholmod_supernodal | multifrontal / cholmod, per round: median (min-max) |")
print("|---|---|---|---|")
print(f"| armadillo_loop1_whole tf | {spread(mf)} | {spread(ch)} | {spread([a / b for a, b in zip(mf, ch)])} |")
PY
cat "$here/table.md"
