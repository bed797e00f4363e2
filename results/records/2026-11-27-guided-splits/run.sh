#!/usr/bin/env bash
# The vertex ordering's METIS splits on the 1-ring graph (analyze_graph's guide; commit in README.md) against the
# splits on the 2-ring graph itself: the TF deformations of the 104k edit at 1 and 2 threads and of the 416k edit
# at 2 threads (multifrontal, --constraints soft --frames 1) by two builds, alternating (the order flips per
# round), each run right after a process that wrote and freed 2 GB (the warm state of ../2026-11-27-fresh-memory).
# Writes runs.csv (every deform row with its provenance, tagged with binary and round), rates.csv (the preparing
# process's machine rates: dgemm, memory read, first touch) and table.md here.
# usage: results/records/2026-11-27-guided-splits/run.sh BASE NEW [ROUNDS [BIG_ROUNDS]]   (from the repository
#        root, after cmake --build build --target exp_machine_rates; the 416k mesh is
#        data/generated/armadillo_loop2.off, made by `meshtool subdivide` from the 104k one)
set -euo pipefail
base=$1 new=$2 rounds=${3:-5} big_rounds=${4:-3}
here=$(cd "$(dirname "$0")" && pwd)
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
rm -f "$here/runs.csv" "$here/rates.csv"
one() {  # label (base or new) edit threads round: one run of that build appended to runs.csv
  local bin=$base; [ "$1" = new ] && bin=$new
  export DEFORMBENCH_THREADS=$3 OPENBLAS_NUM_THREADS=$3
  build/exp_machine_rates --first-touch-mb 2048 --csv "$t/rates.csv" >/dev/null
  if [ -f "$here/rates.csv" ]; then tail -n +2 "$t/rates.csv" >> "$here/rates.csv"; else cp "$t/rates.csv" "$here/rates.csv"; fi
  "$bin" deform "$2" --method tf --constraints soft --frames 1 --solver multifrontal --out "$t/o.ply" \
    --csv "$t/o.csv" >/dev/null
  /usr/bin/python3 scripts/append_rows.py "$t/o.csv" "$here/runs.csv" binary="$1" round="$4"
}
pair() {  # edit threads round: both builds, base first in odd rounds
  if (($3 % 2)); then one base "$@" && one new "$@"; else one new "$@" && one base "$@"; fi
}
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
for ((r = 1; r <= rounds; r++)); do
  for threads in 1 2; do pair data/edits/armadillo_loop1_whole.edit "$threads" "$r"; done
  echo "load after round $r: $(cut -d' ' -f1-3 /proc/loadavg)"
done
for ((r = 1; r <= big_rounds; r++)); do pair data/edits/armadillo_loop2_whole.edit 2 "$r"; done
/usr/bin/python3 - "$here" > "$here/table.md" <<'PY'
import csv, statistics, sys
from collections import defaultdict
here = sys.argv[1]
rows = list(csv.DictReader(open(f"{here}/runs.csv")))
groups = defaultdict(list)
for r in rows: groups[(int(r["vertices"]), int(r["build_threads"]), r["binary"])].append(r)
def med(xs): return "%.3f (%.3f-%.3f)" % (statistics.median(xs), min(xs), max(xs))
print("| vertices | threads | binary | git | runs | analyze s | init s | nnz(L) | GFlop | analyze new / base, per round"
      " | init new / base, per round |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for key in sorted(groups):
    g = groups[key]
    ratio = ["", ""]
    if key[2] == "new":
        for k, col in enumerate(("analyze_s", "init_s")):
            base = {r["round"]: float(r[col]) for r in groups.get(key[:2] + ("base",), [])}
            ratio[k] = ", ".join("%.2f" % (float(r[col]) / base[r["round"]]) for r in g if r["round"] in base)
    nnz = sorted({r["nnz_factor"] for r in g}); fl = sorted({"%.2f" % (float(r["factor_flops"]) / 1e9) for r in g})
    print(f"| {key[0]} | {key[1]} | {key[2]} | {g[0]['git_sha'][:7]} | {len(g)} | "
          f"{med([float(r['analyze_s']) for r in g])} | {med([float(r['init_s']) for r in g])} | {', '.join(nnz)} | "
          f"{', '.join(fl)} | {ratio[0]} | {ratio[1]} |")
PY
cat "$here/table.md"
