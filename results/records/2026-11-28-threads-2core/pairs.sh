#!/usr/bin/env bash
# The 104k TF init under the default METIS vertex ordering and under ringnd, paired: ROUNDS rounds, each running both
# orderings at 1 and at 2 threads, their order flipped every round, one process per run (--frames 1), with
# build/deformbench. Writes pairs.csv (every deform row with its provenance, tagged with its round) and pairs.md
# (each round's init, analysis and factorization, ringnd / default per round).
# usage: results/records/2026-11-28-threads-2core/pairs.sh ROUNDS   (from the repository root)
set -euo pipefail
rounds=${1:?ROUNDS}
here=$(cd "$(dirname "$0")" && pwd)
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
out=$here/pairs.csv; rm -f "$out"
for ((r = 1; r <= rounds; r++)); do
  if ((r % 2)); then order=(default ringnd); else order=(ringnd default); fi
  for T in 1 2; do for o in "${order[@]}"; do
    echo "$(date -u +%H:%M:%S) load $(cut -d' ' -f1-3 /proc/loadavg): round $r T=$T $o" | tee -a "$here/pairs.log"
    DEFORMBENCH_THREADS=$T OPENBLAS_NUM_THREADS=$T build/deformbench deform data/edits/armadillo_loop1_whole.edit \
      --method tf --constraints soft --frames 1 --ordering "$o" --out "$t/o.ply" --csv "$t/one.csv" > /dev/null
    /usr/bin/python3 scripts/append_rows.py "$t/one.csv" "$out" round=$r ordering=$o
  done; done
done
/usr/bin/python3 - "$out" > "$here/pairs.md" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
by = {}
for r in rows:
    by.setdefault((r["build_threads"], r["round"]), {})[r["ordering"]] = r
print("| T | round | default init s (analyze, factorize) | ringnd init s (analyze, factorize) | ringnd / default init |"
      " GFlop, default / ringnd |")
print("|---|---|---|---|---|---|")
f = lambda r: f"{float(r['init_s']):.2f} ({float(r['analyze_s']):.2f}, {float(r['factorize_s']):.2f})"
for (T, k) in sorted(by, key=lambda x: (int(x[0]), int(x[1]))):
    d, g = by[(T, k)]["default"], by[(T, k)]["ringnd"]
    print(f"| {T} | {k} | {f(d)} | {f(g)} | {float(g['init_s']) / float(d['init_s']):.2f} | "
          f"{float(d['factor_flops']) / 1e9:.1f} / {float(g['factor_flops']) / 1e9:.1f} |")
PY
cat "$here/pairs.md"
