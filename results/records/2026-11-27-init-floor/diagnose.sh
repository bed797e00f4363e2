#!/usr/bin/env bash
# Where the 104k TF init goes, step by step, with a diagnostic build: phases.patch (the deform command's memory
# check, the ordering's and the structured build's steps) and front_buckets.patch (factor_supernode's steps summed
# per front size), applied to the commit in README.md and built as build/deformbench, then copied aside as DIAG.
# Each round runs the deformation at 1 and at 2 threads in two states of the machine's memory (cold: after SETTLE
# seconds of nothing; warm: right after a process that wrote and freed 2 GB, as ../2026-11-27-fresh-memory/run.sh),
# and times the whole command too. Writes diag.txt (the printed lines, labelled) and diag.md (medians) here.
# usage: results/records/2026-11-27-init-floor/diagnose.sh DIAG [ROUNDS]   (from the repository root; needs
#        build/exp_machine_rates)
set -euo pipefail
diag=$1 rounds=${2:-3} settle=${SETTLE:-8}
here=$(cd "$(dirname "$0")" && pwd)
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
: > "$here/diag.txt"
for ((r = 1; r <= rounds; r++)); do
  for state in cold warm; do
    for threads in 1 2; do
      if [ "$state" = cold ]; then sleep "$settle"; else build/exp_machine_rates --gemm-size 64 --first-touch-mb 2048 >/dev/null; fi
      start=$(date +%s.%N)
      DEFORMBENCH_THREADS=$threads OPENBLAS_NUM_THREADS=$threads "$diag" deform data/edits/armadillo_loop1_whole.edit \
        --method tf --constraints soft --frames 1 --solver multifrontal --out "$t/o.ply" --csv "$t/o.csv" \
        2> "$t/err" >/dev/null
      awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "PHASE command %.4f\n", b - a }' >> "$t/err"
      /usr/bin/python3 - "$t/o.csv" >> "$t/err" <<'PY'
import csv, sys
r = list(csv.DictReader(open(sys.argv[1])))[0]
print("CSV", *(r[k] for k in ("build_s", "analyze_s", "factorize_s", "factorize_top_s", "init_s", "git_sha")))
PY
      sed "s/^/$r $state $threads /" "$t/err" >> "$here/diag.txt"
    done
  done
done
/usr/bin/python3 - "$here" > "$here/diag.md" <<'PY'
import collections, statistics, sys
here = sys.argv[1]
def med(xs): return "%.3f (%.3f-%.3f)" % (statistics.median(xs), min(xs), max(xs)) if xs else ""
phase = collections.defaultdict(list)   # (state, threads, name) -> seconds per run (summed within a run)
fronts = collections.defaultdict(list)  # (state, rows) -> [count, steps..., gflop, mentries] per run
csvs = collections.defaultdict(list)
for line in open(f"{here}/diag.txt"):
    f = line.split()
    if len(f) < 4: continue
    key = (f[1], int(f[2]))
    if f[3] == "PHASE": phase[key + (f[4], f[0])].append(float(f[5]))
    elif f[3] == "FRONTS" and key[1] == 1: fronts[(f[1], int(f[4]))].append([float(x) for x in f[5:]])
    elif f[3] == "CSV": csvs[key].append([float(x) for x in f[4:9]])
runs = collections.defaultdict(dict)  # each step prints once per run (the patch times only the run's METIS ordering)
for (state, threads, name, rnd), xs in phase.items(): runs[(state, threads, name)][rnd] = sum(xs)
print("| state | threads | init s | build s | analyze s | factorize s | top phase s |")
print("|---|---|---|---|---|---|---|")
for (state, threads), rows in sorted(csvs.items()):
    cols = list(zip(*rows))
    print(f"| {state} | {threads} | {med(cols[4])} | {med(cols[0])} | {med(cols[1])} | {med(cols[2])} | {med(cols[3])} |")
print()
names = ["command", "memory_check", "ordering_pattern", "ordering", "postorder_analysis", "build_pattern", "build_expand", "build_fill", "build_coupling"]
print("| state | threads | " + " | ".join(names) + " |")
print("|---|---|" + "---|" * len(names))
for state in ("cold", "warm"):
    for threads in (1, 2):
        print(f"| {state} | {threads} | " + " | ".join(med(list(runs[(state, threads, n)].values())) for n in names) + " |")
print()
print("One thread, factor_supernode's steps summed per front size (median over the rounds; s):")
print()
print("| state | front rows | fronts | children's pivot part | matrix entries | panels | update | children's update part | GFlop | GFlop/s of panels + update | M child entries | ns per child entry |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|")
for (state, rows), xs in sorted(fronts.items()):
    m = [statistics.median(c) for c in zip(*xs)]
    count, a1, ent, pan, upd, a2, gf, me = m
    rate = gf / (pan + upd) if pan + upd > 0 else 0
    per = (a1 + a2) / me * 1e3 if me > 0 else 0
    print(f"| {state} | {rows}-{2 * rows - 1} | {count:.0f} | {a1:.3f} | {ent:.3f} | {pan:.3f} | {upd:.3f} | {a2:.3f} | {gf:.2f} | {rate:.1f} | {me:.1f} | {per:.1f} |")
PY
cat "$here/diag.md"
