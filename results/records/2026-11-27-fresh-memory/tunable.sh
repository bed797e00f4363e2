#!/usr/bin/env bash
# The C library's own huge-page policy for every process-wide allocation (glibc >= 2.35: GLIBC_TUNABLES=
# glibc.malloc.hugetlb=1 makes malloc advise its mapped blocks for transparent huge pages), which would reach the
# allocations the project cannot hook (METIS's, MUMPS's, Eigen's). Per round, alternating, each run after SETTLE
# seconds of idle: (a) the 104k TF deformation with MUMPS and with the multifrontal backend, default and with the
# tunable; (b) exp_analysis (vertex ordering + symbolic analysis) of the same edit in a fresh process, default
# and with the tunable. Writes tunable_deform.csv, tunable_analysis.csv (rows with provenance + policy, round)
# and tunable.md here.
# usage: results/records/2026-11-27-fresh-memory/tunable.sh ROUNDS   (from the repository root, after building
#        deformbench and exp_analysis in build/)
set -euo pipefail
rounds=${1:-2}
settle=${SETTLE:-8}
here=$(cd "$(dirname "$0")" && pwd)
export DEFORMBENCH_THREADS=2 OPENBLAS_NUM_THREADS=2
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
py=/usr/bin/python3
append() {  # CSV POLICY ROUND OUT
  "$py" - "$@" <<'PY'
import csv, os, sys
src, policy, rnd, out = sys.argv[1:5]
rows = list(csv.DictReader(open(src)))
new = not os.path.exists(out)
with open(out, "a", newline="") as f:
    w = csv.DictWriter(f, fieldnames=["policy", "round"] + list(rows[0].keys()))
    if new: w.writeheader()
    for r in rows: w.writerow({"policy": policy, "round": rnd, **r})
PY
}
with() {  # POLICY CMD...: CMD under the policy
  local policy=$1; shift
  if [ "$policy" = hugetlb ]; then GLIBC_TUNABLES=glibc.malloc.hugetlb=1 "$@"; else "$@"; fi
}
rm -f "$here/tunable_deform.csv" "$here/tunable_analysis.csv"
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
for ((r = 1; r <= rounds; r++)); do
  for b in mumps multifrontal; do
    for policy in default hugetlb; do
      sleep "$settle"
      with "$policy" build/deformbench deform data/edits/armadillo_loop1_whole.edit --method tf --constraints soft \
        --frames 1 --solver "$b" --out "$t/o.ply" --csv "$t/o.csv" >/dev/null
      append "$t/o.csv" "$policy" "$r" "$here/tunable_deform.csv"
    done
  done
  for policy in default hugetlb; do
    sleep "$settle"
    with "$policy" build/exp_analysis --edit data/edits/armadillo_loop1_whole.edit --system tf --orderings metis \
      --rounds 1 --csv "$t/a.csv" >/dev/null
    append "$t/a.csv" "$policy" "$r" "$here/tunable_analysis.csv"
  done
  echo "load after round $r: $(cut -d' ' -f1-3 /proc/loadavg)"
done
"$py" - "$here" > "$here/tunable.md" <<'PY'
import csv, statistics, sys
here = sys.argv[1]
def med(xs): return "%.3f (%.3f-%.3f)" % (statistics.median(xs), min(xs), max(xs))
rows = list(csv.DictReader(open(f"{here}/tunable_deform.csv")))
print("| backend | policy | init s | analyze s | factorize s | init hugetlb / default, per round |")
print("|---|---|---|---|---|---|")
for b in ("mumps", "multifrontal"):
    for p in ("default", "hugetlb"):
        rs = [r for r in rows if r["backend"] == b and r["policy"] == p]
        ratio = ""
        if p == "hugetlb":
            d = {r["round"]: float(r["init_s"]) for r in rows if r["backend"] == b and r["policy"] == "default"}
            ratio = med([float(r["init_s"]) / d[r["round"]] for r in rs])
        print(f"| {b} | {p} | {med([float(r['init_s']) for r in rs])} | {med([float(r['analyze_s']) for r in rs])} | "
              f"{med([float(r['factorize_s']) for r in rs])} | {ratio} |")
rows = list(csv.DictReader(open(f"{here}/tunable_analysis.csv")))
print()
print("| exp_analysis, 104k TF metis | policy | order s | order CPU s | symbolic s | analysis s |")
print("|---|---|---|---|---|---|")
for p in ("default", "hugetlb"):
    rs = [r for r in rows if r["policy"] == p]
    print(f"| | {p} | {med([float(r['order_s']) for r in rs])} | {med([float(r['order_cpu_s']) for r in rs])} | "
          f"{med([float(r['mf_analyze_s']) for r in rs])} | {med([float(r['analysis_s']) for r in rs])} |")
print()
print(f"git {rows[0]['git_sha']}; {len(rows)} analysis rows.")
PY
cat "$here/tunable.md"
