#!/usr/bin/env bash
# The page policy of CHOLMOD's memory (commit 59386db: SuiteSparse's blocks of 4 MB or more advised for huge pages,
# as the multifrontal backend's factor already was): the 104k TF init of CHOLMOD supernodal and of the multifrontal
# backend, built before (BASE) and after (NEW) that commit, alternating, each run after SETTLE seconds of idle (the
# "cold" state of run.sh). Also the multifrontal / CHOLMOD init ratio per round and build (issue 31's 2-core target:
# <= 0.6). Writes pages.csv (deform rows with provenance + binary, round) and pages.md here.
# usage: results/records/2026-11-27-fresh-memory/pages.sh ROUNDS BASE_BINARY BASE_SHA NEW_BINARY NEW_SHA
#        (from the repository root; each binary's rows carry its SHA: binaries built before 12b867b report the
#        tree's HEAD when they run, which is not the commit they were built from)
#        results/records/2026-11-27-fresh-memory/pages.sh report   (pages.md again from pages.csv)
set -euo pipefail
report() {
  /usr/bin/python3 - "$here" > "$here/pages.md" <<'PY'
import csv, statistics, sys
here = sys.argv[1]
rows = list(csv.DictReader(open(f"{here}/pages.csv")))
def med(xs): return "%.3f (%.3f-%.3f)" % (statistics.median(xs), min(xs), max(xs))
def get(b, binary, key): return {r["round"]: float(r[key]) for r in rows if r["backend"] == b and r["binary"] == binary}
print("| backend | binary | git | init s | analyze s | factorize s | factorize new / base, per round |")
print("|---|---|---|---|---|---|---|")
for b in ("cholmod_supernodal", "multifrontal"):
    for binary in ("base", "new"):
        rs = [r for r in rows if r["backend"] == b and r["binary"] == binary]
        ratio = ""
        if binary == "new":
            base = get(b, "base", "factorize_s")
            ratio = med([float(r["factorize_s"]) / base[r["round"]] for r in rs])
        print(f"| {b} | {binary} | {rs[0]['git_sha']} | {med([float(r['init_s']) for r in rs])} | "
              f"{med([float(r['analyze_s']) for r in rs])} | {med([float(r['factorize_s']) for r in rs])} | {ratio} |")
print()
print("| binary | init multifrontal / CHOLMOD, per round |")
print("|---|---|")
for binary in ("base", "new"):
    mf, ch = get("multifrontal", binary, "init_s"), get("cholmod_supernodal", binary, "init_s")
    print(f"| {binary} | {med([mf[k] / ch[k] for k in mf])} |")
r0 = rows[0]
print()
print(f"{r0['blas']} core {r0['blas_core']}, {r0['blas_threads']} BLAS threads, {r0['build_threads']} build threads, "
      f"{r0['cpu']}, {r0['compiler']}; {len(rows)} rows.")
PY
  cat "$here/pages.md"
}
here=$(cd "$(dirname "$0")" && pwd)
if [ "$1" = report ]; then report; exit 0; fi
rounds=$1 base=$2 base_sha=$3 new=$4 new_sha=$5
settle=${SETTLE:-8}
export DEFORMBENCH_THREADS=2 OPENBLAS_NUM_THREADS=2
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
py=/usr/bin/python3
rm -f "$here/pages.csv"
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
for ((r = 1; r <= rounds; r++)); do
  for b in cholmod_supernodal multifrontal; do
    for binary in base new; do
      exe=$base sha=$base_sha
      [ "$binary" = new ] && exe=$new sha=$new_sha
      sleep "$settle"
      DEFORMBENCH_GIT_SHA=$sha "$exe" deform data/edits/armadillo_loop1_whole.edit --method tf --constraints soft --frames 1 --solver "$b" \
        --out "$t/o.ply" --csv "$t/o.csv" >/dev/null
      "$py" - "$t/o.csv" "$binary" "$r" "$here/pages.csv" <<'PY'
import csv, os, sys
src, binary, rnd, out = sys.argv[1:5]
rows = list(csv.DictReader(open(src)))
new = not os.path.exists(out)
with open(out, "a", newline="") as f:
    w = csv.DictWriter(f, fieldnames=["binary", "round"] + list(rows[0].keys()))
    if new: w.writeheader()
    for row in rows: w.writerow({"binary": binary, "round": rnd, **row})
PY
    done
  done
  echo "load after round $r: $(cut -d' ' -f1-3 /proc/loadavg)"
done
report
