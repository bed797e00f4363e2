#!/usr/bin/env bash
# The deform command's memory check before and after the multifrontal backend checks its own factor (commit in
# README.md): the same 104k and 416k TF deformations (multifrontal, the default budget) by two builds, alternating
# (the order rotates per round), SETTLE seconds of idle before each run. Per run: the command's wall time (date
# around it), its deform row (init and its split, peak RSS, provenance) and the mesh it wrote, compared byte for
# byte with the other build's of the same round. Writes runs.csv and table.md here.
# usage: results/records/2026-11-27-memory-check/run.sh BASE NEW [ROUNDS_104K] [ROUNDS_416K]   (from the repository
#        root; data/generated/armadillo_loop2.off as in README.md)
set -euo pipefail
base=$1 new=$2 r1=${3:-4} r2=${4:-2} settle=${SETTLE:-3}
here=$(cd "$(dirname "$0")" && pwd)
export DEFORMBENCH_THREADS=2 OPENBLAS_NUM_THREADS=2
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
rm -f "$here/runs.csv"
one() {  # binary-label binary edit round: one run appended to runs.csv
  sleep "$settle"
  local start; start=$(date +%s.%N)
  "$2" deform "data/edits/$3.edit" --method tf --constraints soft --frames 1 --out "$t/$1.ply" --csv "$t/o.csv" >/dev/null
  local wall; wall=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.4f", b - a }')
  /usr/bin/python3 - "$t/o.csv" "$here/runs.csv" "$1" "$3" "$4" "$wall" <<'PY'
import csv, os, sys
src, out, binary, edit, rnd, wall = sys.argv[1:7]
row = list(csv.DictReader(open(src)))[0]
new = not os.path.exists(out)
with open(out, "a", newline="") as f:
    w = csv.DictWriter(f, fieldnames=["binary", "edit_name", "round", "command_s"] + list(row.keys()))
    if new: w.writeheader()
    w.writerow({**row, "binary": binary, "edit_name": edit, "round": rnd, "command_s": wall})
PY
}
for edit in armadillo_loop1_whole armadillo_loop2_whole; do
  rounds=$r1; [ "$edit" = armadillo_loop2_whole ] && rounds=$r2
  for ((r = 1; r <= rounds; r++)); do
    if ((r % 2)); then order="base new"; else order="new base"; fi
    for b in $order; do
      if [ "$b" = base ]; then one base "$base" "$edit" "$r"; else one new "$new" "$edit" "$r"; fi
    done
    cmp -s "$t/base.ply" "$t/new.ply" && echo "$edit round $r: the meshes are identical" \
      || echo "$edit round $r: the meshes DIFFER"
  done
done | tee "$here/cmp.txt"
/usr/bin/python3 - "$here" > "$here/table.md" <<'PY'
import collections, csv, statistics, sys
here = sys.argv[1]
rows = list(csv.DictReader(open(f"{here}/runs.csv")))
def med(xs): return "%.3f (%.3f-%.3f)" % (statistics.median(xs), min(xs), max(xs))
print("| edit | binary | command s | init s | command - init - frame s | peak RSS MB | command new / base, per round |")
print("|---|---|---|---|---|---|---|")
for edit in dict.fromkeys(r["edit_name"] for r in rows):
    for b in ("base", "new"):
        rs = [r for r in rows if r["edit_name"] == edit and r["binary"] == b]
        outside = [float(r["command_s"]) - float(r["init_s"]) - float(r["frame_s"]) for r in rs]
        ratio = ""
        if b == "new":
            base = {r["round"]: float(r["command_s"]) for r in rows if r["edit_name"] == edit and r["binary"] == "base"}
            ratio = ", ".join("%.3f" % (float(r["command_s"]) / base[r["round"]]) for r in rs)
        print(f"| {edit} | {b} {rs[0]['git_sha']} | {med([float(r['command_s']) for r in rs])} | "
              f"{med([float(r['init_s']) for r in rs])} | {med(outside)} | "
              f"{med([float(r['peak_rss_bytes']) / 1e6 for r in rs])} | {ratio} |")
r0 = rows[0]
print()
print(f"{r0['blas']} core {r0['blas_core']}, {r0['blas_threads']} BLAS threads, {r0['build_threads']} build threads, "
      f"{r0['cpu']}, {r0['compiler']}; {len(rows)} runs.")
PY
cat "$here/table.md"
