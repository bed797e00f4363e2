#!/usr/bin/env bash
# The factorization's top phase on a team of threads sharing each front in tiles (solvers/base/team.h, front.h)
# against the build before it, whose top phase ran each front's BLAS calls on OpenBLAS's own threads. In each
# round both binaries alternate (base first in odd rounds) on the 104k TF and LAP edits
# (data/edits/armadillo_loop1_whole.edit, 2 threads, --constraints soft --frames 3, multifrontal), first on a quiet
# machine, then beside a busy loop that holds one core (another process's work, as on a shared machine); then
# BIG_ROUNDS rounds of the 416k TF edit, quiet. Every run follows a process that wrote and freed 2 GB, so that both
# binaries start in the same memory state. Writes deform.csv (every deform row with its provenance, plus binary,
# state and round columns) and table.md here, or in OUT when set (a later record's comparison of two builds).
# usage: results/records/2026-11-27-top-team/run.sh ROUNDS BASE_BINARY NEW_BINARY   (from the repository root,
#        after building exp_machine_rates in build/; the 416k mesh is data/generated/armadillo_loop2.off, made by
#        `meshtool subdivide` from the 104k one). BIG_ROUNDS (default 2; 0 skips the 416k runs).
set -euo pipefail
rounds=${1:?ROUNDS} base=${2:?BASE_BINARY} new=${3:?NEW_BINARY}
big_rounds=${BIG_ROUNDS:-2}
here=${OUT:-$(cd "$(dirname "$0")" && pwd)}
export DEFORMBENCH_THREADS=2 OPENBLAS_NUM_THREADS=2
t=$(mktemp -d); busy=
trap '[ -z "$busy" ] || kill "$busy" 2>/dev/null; rm -rf "$t"' EXIT
py=/usr/bin/python3
append() {  # CSV BINARY STATE ROUND: the deform row, with binary, state and round columns, into deform.csv
  "$py" - "$@" "$here/deform.csv" <<'PY'
import csv, os, sys
src, binary, state, rnd, out = sys.argv[1:6]
rows = list(csv.DictReader(open(src)))
new = not os.path.exists(out)
with open(out, "a", newline="") as f:
    w = csv.DictWriter(f, fieldnames=["binary", "state", "round"] + list(rows[0].keys()))
    if new: w.writeheader()
    for r in rows: w.writerow({"binary": binary, "state": state, "round": rnd, **r})
PY
}
deform() {  # EDIT METHOD STATE ROUND: both binaries, base first in odd rounds, new first in even ones
  local order="base new"; [ $(($4 % 2)) = 1 ] || order="new base"
  for b in $order; do
    local bin=$base; [ $b = base ] || bin=$new
    # Each run right after a process that wrote and freed 2 GB: on this VM memory nobody freed in the last
    # seconds is backed by the host only on first touch (records/2026-11-27-fresh-memory), so a run right after
    # the other binary's would otherwise start warmer than one after a pause.
    build/exp_machine_rates --gemm-size 64 --first-touch-mb 2048 >/dev/null
    "$bin" deform "$1" --method "$2" --constraints soft --frames 3 --solver multifrontal --out "$t/o.ply" \
      --csv "$t/o.csv" >/dev/null
    append "$t/o.csv" "$b" "$3" "$4"
  done
}
rm -f "$here/deform.csv"
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
for ((r = 1; r <= rounds; r++)); do
  for state in quiet busy; do
    if [ $state = busy ]; then sh -c 'while :; do :; done' & busy=$!; fi
    for m in tf lap; do deform data/edits/armadillo_loop1_whole.edit $m $state $r; done
    if [ -n "$busy" ]; then kill "$busy"; wait "$busy" 2>/dev/null || true; busy=; fi
  done
  echo "load after round $r: $(cut -d' ' -f1-3 /proc/loadavg)"
done
for ((r = 1; r <= big_rounds; r++)); do deform data/edits/armadillo_loop2_whole.edit tf quiet $r; done
"$py" - "$here" > "$here/table.md" <<'PY'
import csv, statistics, sys
from collections import defaultdict
here = sys.argv[1]
rows = list(csv.DictReader(open(f"{here}/deform.csv")))
def med(xs, f="%.3f"): return (f + " (" + f + "-" + f + ")") % (statistics.median(xs), min(xs), max(xs))
groups = defaultdict(list)
for r in rows: groups[(r["vertices"], r["method"], r["state"], r["binary"])].append(r)
print("| vertices | method | state | binary | git | rounds | init s | factorize s | top phase s | top phase GFlop/s |"
      " top phase new / base, per round | factorize new / base, per round |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|")
for key in sorted(groups, key=lambda k: (int(k[0]), k[1], k[2] != "quiet", k[3])):
    g = groups[key]
    top = [float(r["factorize_top_s"]) for r in g]
    rate = [float(r["factor_top_flops"]) / float(r["factorize_top_s"]) / 1e9 for r in g]
    ratio = ["", ""]
    if key[3] == "new":
        for k, col in enumerate(("factorize_top_s", "factorize_s")):
            base = {r["round"]: float(r[col]) for r in groups.get(key[:3] + ("base",), [])}
            ratio[k] = ", ".join("%.2f" % (float(r[col]) / base[r["round"]]) for r in g if r["round"] in base)
    print(f"| {key[0]} | {key[1]} | {key[2]} | {key[3]} | {g[0]['git_sha'][:7]} | {len(g)} | "
          f"{med([float(r['init_s']) for r in g])} | {med([float(r['factorize_s']) for r in g])} | {med(top)} | "
          f"{med(rate, '%.0f')} | {ratio[0]} | {ratio[1]} |")
r0 = rows[0]
print(f"\n{r0['blas']} core {r0['blas_core']}, {r0['blas_threads']} BLAS threads, "
      f"{r0['cpu']}, {r0['compiler']}; {len(rows)} rows.")
PY
cat "$here/table.md"
