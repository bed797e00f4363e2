#!/usr/bin/env bash
# How much of an init is the first touch of fresh memory, and how it depends on what the machine freed moments
# before. On a virtual machine whose host backs guest memory only on first use and takes back what the guest
# frees (free page reporting), a process that writes memory nobody used in the last seconds waits for the host;
# memory another process gave back just before is fast again. Each round measures, in alternation:
#   cold: after SETTLE seconds of nothing, exp_machine_rates' first-touch rate, then after SETTLE more seconds the
#         104k TF deformation (multifrontal, then CHOLMOD supernodal);
#   warm: the same, each right after a process that wrote and freed WARM_MB of memory (exp_machine_rates
#         --first-touch-mb WARM_MB).
# Writes rates.csv (exp_machine_rates rows + state, round), deform.csv (deform rows with provenance + state, round)
# and table.md here, or in the folder OUT names (a later record's run of this script).
# usage: results/records/2026-11-27-fresh-memory/run.sh ROUNDS   (from the repository root, after building
#        deformbench and exp_machine_rates in build/). SETTLE (default 8 s), WARM_MB (default 2048), OUT.
set -euo pipefail
rounds=${1:-3}
settle=${SETTLE:-8} warm_mb=${WARM_MB:-2048}
here=${OUT:-$(cd "$(dirname "$0")" && pwd)}
export DEFORMBENCH_THREADS=2 OPENBLAS_NUM_THREADS=2
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
py=/usr/bin/python3
append() {  # CSV STATE ROUND OUT: the CSV's row(s) with state and round columns, into OUT (header once)
  "$py" - "$@" <<'PY'
import csv, os, sys
src, state, rnd, out = sys.argv[1:5]
rows = list(csv.DictReader(open(src)))
new = not os.path.exists(out)
with open(out, "a", newline="") as f:
    w = csv.DictWriter(f, fieldnames=["state", "round"] + list(rows[0].keys()))
    if new: w.writeheader()
    for r in rows: w.writerow({"state": state, "round": rnd, **r})
PY
}
prepare() {  # STATE: what the machine did just before the measurement
  if [ "$1" = cold ]; then sleep "$settle"; else build/exp_machine_rates --gemm-size 64 --first-touch-mb "$warm_mb" >/dev/null; fi
}
rm -f "$here/rates.csv" "$here/deform.csv"
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
for ((r = 1; r <= rounds; r++)); do
  for state in cold warm; do
    prepare "$state"
    build/exp_machine_rates --csv "$t/r.csv" >/dev/null
    append "$t/r.csv" "$state" "$r" "$here/rates.csv"
    for b in multifrontal cholmod_supernodal; do
      prepare "$state"
      build/deformbench deform data/edits/armadillo_loop1_whole.edit --method tf --constraints soft --frames 1 \
        --solver "$b" --out "$t/o.ply" --csv "$t/o.csv" >/dev/null
      append "$t/o.csv" "$state" "$r" "$here/deform.csv"
    done
  done
  echo "load after round $r: $(cut -d' ' -f1-3 /proc/loadavg)"
done
"$py" - "$here" > "$here/table.md" <<'PY'
import csv, statistics, sys, collections
here = sys.argv[1]
def med(xs): return "%.3f (%.3f-%.3f)" % (statistics.median(xs), min(xs), max(xs))
rates = list(csv.DictReader(open(f"{here}/rates.csv")))
print("| state | first touch GB/s: median (min-max) | dgemm GFlop/s | memory read GB/s |")
print("|---|---|---|---|")
for s in ("cold", "warm"):
    rs = [r for r in rates if r["state"] == s]
    print(f"| {s} | {med([float(r['first_touch_bytes_per_s'])/1e9 for r in rs])} | "
          f"{med([float(r['blas_dgemm_flops'])/1e9 for r in rs])} | {med([float(r['memory_read_bytes_per_s'])/1e9 for r in rs])} |")
print()
rows = list(csv.DictReader(open(f"{here}/deform.csv")))
print("| backend | state | init s | build s | analyze s | factorize s | factor MB | factorize: warm / cold, per round |")
print("|---|---|---|---|---|---|---|---|")
for b in ("multifrontal", "cholmod_supernodal"):
    for s in ("cold", "warm"):
        rs = [r for r in rows if r["backend"] == b and r["state"] == s]
        ratio = ""
        if s == "warm":
            cold = {r["round"]: float(r["factorize_s"]) for r in rows if r["backend"] == b and r["state"] == "cold"}
            ratio = med([float(r["factorize_s"]) / cold[r["round"]] for r in rs])
        print(f"| {b} | {s} | {med([float(r['init_s']) for r in rs])} | {med([float(r['build_s']) for r in rs])} | "
              f"{med([float(r['analyze_s']) for r in rs])} | {med([float(r['factorize_s']) for r in rs])} | "
              f"{float(rs[0]['factor_bytes'])/1e6:.0f} | {ratio} |")
print()
print("| state | init multifrontal / CHOLMOD, per round | median |")
print("|---|---|---|")
for s in ("cold", "warm"):
    init = {(r["round"], r["backend"]): float(r["init_s"]) for r in rows if r["state"] == s}
    ratios = [init[(k, "multifrontal")] / init[(k, "cholmod_supernodal")]
              for k in sorted({k for k, _ in init}, key=int) if (k, "cholmod_supernodal") in init]
    print(f"| {s} | {', '.join('%.3f' % x for x in ratios)} | {statistics.median(ratios):.3f} |")
r0 = rows[0]
print()
print(f"git {r0['git_sha']}, {r0['blas']} core {r0['blas_core']}, {r0['blas_threads']} BLAS threads, "
      f"{r0['build_threads']} build threads, {r0['cpu']}, {r0['compiler']}; {len(rows)} deform rows.")
PY
cat "$here/table.md"
