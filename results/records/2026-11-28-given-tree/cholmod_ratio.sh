#!/usr/bin/env bash
# Issue 31's 2-core target "init <= 0.6x CHOLMOD's in the same run": the 104k TF deformation's init (one frame) by
# the multifrontal backend and by cholmod_supernodal, alternating, ROUNDS rounds at 2 threads, with build/deformbench.
# Writes init_vs_cholmod_2.csv (every deform row, with provenance) and appends the per-round ratios to table.md.
# usage: results/records/2026-11-28-given-tree/cholmod_ratio.sh ROUNDS   (from the repository root)
set -euo pipefail
rounds=${1:?ROUNDS}
here=$(cd "$(dirname "$0")" && pwd)
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
export DEFORMBENCH_THREADS=2 OPENBLAS_NUM_THREADS=2
out="$here/init_vs_cholmod_2.csv"; rm -f "$out"
for ((r = 1; r <= rounds; r++)); do
  if ((r % 2)); then order=(multifrontal cholmod_supernodal); else order=(cholmod_supernodal multifrontal); fi
  for s in "${order[@]}"; do
    echo "$(date -u +%H:%M:%S) load $(cut -d' ' -f1-3 /proc/loadavg): round $r $s" | tee -a "$here/run.log"
    build/deformbench deform data/edits/armadillo_loop1_whole.edit --method tf --constraints soft --frames 1 \
      --solver "$s" --out "$t/o.ply" --csv "$t/one.csv" > /dev/null
    [ -s "$out" ] || { printf 'round,'; head -1 "$t/one.csv"; } > "$out"
    tail -n +2 "$t/one.csv" | sed "s/^/$r,/" >> "$out"
  done
done
/usr/bin/python3 - "$out" >> "$here/table.md" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
by = {}
for r in rows: by.setdefault(r["round"], {})[r["backend"]] = r
print("\n104k TF init, 2 threads, multifrontal against cholmod_supernodal in the same rounds (cholmod_ratio.sh):\n")
print("| round | multifrontal init s (analyze, factorize) | cholmod_supernodal init s (analyze, factorize) | ratio |")
print("|---|---|---|---|")
for k in sorted(by, key=int):
    m, c = by[k]["multifrontal"], by[k]["cholmod_supernodal"]
    f = lambda r: f"{float(r['init_s']):.2f} ({float(r['analyze_s']):.2f}, {float(r['factorize_s']):.2f})"
    print(f"| {k} | {f(m)} | {f(c)} | {float(m['init_s']) / float(c['init_s']):.2f} |")
PY
tail -8 "$here/table.md"
