#!/usr/bin/env bash
# Thread scaling on a lent 16-core device machine (issue 31 item 4), prepared for a session that has one:
# T = 1 2 4 8 16; the 104k and 416k armadillo TF and LAP edits; multifrontal and CHOLMOD (supernodal); one
# process per run; init split (build, analyze, factorize), full-frame median, factorization GFlop/s, the
# multifrontal factorization's serial top phase (its time and share of the flops: what limits it beyond 8 threads,
# issue 31 item 3) and the parallel efficiency t(1) / (T t(T)). Three steps:
#   DEVICE_BUNDLE=PATH/device-bundle.sh scripts/device_threads.sh prepare
#                                                # here: bundle build/ with the device tool's bundler (not part of
#                                                # the project) and the 104k mesh into .device/ (git-ignored)
#   run tool: carry [".device"], timeout_s 590, command
#       bash .device/device_threads.sh run       # there: writes $OUT/threads.csv and $OUT/machine.txt
#   scripts/device_threads.sh report FILES_AT results/records/DATE-threads   # here: the record's CSV and table
# The device run stops starting runs after DEADLINE seconds (default 540), most needed first (104k, then 416k
# multifrontal, then 416k CHOLMOD, then TF under the ringnd ordering at 8 and 16 threads); a run not started is
# absent from the CSV, and the report says which. The vertex ordering is the default (METIS for TF: one more
# dissection level per doubling of the threads beyond two) unless the row's `ordering` says otherwise.
set -euo pipefail
mode=${1:-}
case $mode in
prepare)
  "${DEVICE_BUNDLE:?DEVICE_BUNDLE names the device-bundle.sh of the device tool library}" build .device deformbench meshtool
  gzip -c data/generated/armadillo_loop1.off > .device/armadillo_loop1.off.gz
  cp "$0" .device/device_threads.sh
  du -sh .device ;;
run)
  D=${BUNDLE:-$PWD/.device}; O=${OUT:?OUT is the device tool\'s output folder}
  export LD_LIBRARY_PATH=$D/lib
  deadline=$((SECONDS + ${DEADLINE:-540}))
  W=$(mktemp -d); cd "$W"
  { lscpu | head -25; head -3 /proc/meminfo; cat /proc/loadavg; ldd "$D/bin/deformbench" | grep -E "not found|openblas"; } > "$O/machine.txt" 2>&1
  gunzip -c "$D/armadillo_loop1.off.gz" > l1.off
  "$D/bin/meshtool" subdivide l1.off l2.off 1 > /dev/null 2>&1 || echo "subdivide failed" >> "$O/machine.txt"
  for k in 1 2; do  # the edit of data/edits/armadillo_loop1_whole.edit on the 104k (1) and 416k (2) meshes
    printf 'mesh = l%s.off\nroi = all\nhandle = nearest:-20.2599,97.1076,-28.8554,100\ntransform = translate:0,10,0\n' $k > e$k.edit
  done
  cols="build_s analyze_s factorize_s init_s frame_s factor_flops factorize_top_s factor_top_flops"
  echo "tier,method,solver,threads,ordering,rc,${cols// /,}" > "$O/threads.csv"
  one() {  # tier method solver threads [ordering]
    [ $SECONDS -lt $deadline ] || return 0
    local rc=0 ord=${5:-default}
    DEFORMBENCH_THREADS=$4 OPENBLAS_NUM_THREADS=$4 OMP_NUM_THREADS=$4 timeout 150 "$D/bin/deformbench" deform e$1.edit \
      --method "$2" --constraints soft --frames 5 --solver "$3" --ordering "$ord" --out o.ply --csv o.csv > log 2>&1 || rc=$?
    if [ $rc -eq 0 ]; then
      python3 -c 'import csv,sys; r=next(csv.DictReader(open("o.csv"))); print(",".join([*sys.argv[2:], "0"] + [r[k] for k in sys.argv[1].split()]))' "$cols" "$1" "$2" "$3" "$4" "$ord" >> "$O/threads.csv"
    else
      echo "$1,$2,$3,$4,$ord,$rc,,,,,,,," >> "$O/threads.csv"; tail -3 log >> "$O/machine.txt"
    fi
  }
  for T in 1 2 4 8 16; do for S in multifrontal cholmod_supernodal; do for M in tf lap; do one 1 $M $S $T; done; done; done
  for T in 16 8 4 2 1; do for M in tf lap; do one 2 $M multifrontal $T; done; done
  for T in 16 8 2; do for M in tf lap; do one 2 $M cholmod_supernodal $T; done; done
  # The 1-ring dissection (ringnd: every level on threads, the same ordering for every thread count) beside METIS's
  # (one more level per doubling of the threads), last: the analysis on 16 cores by both.
  for k in 1 2; do for T in 16 8; do one $k tf multifrontal $T ringnd; done; done
  cat "$O/threads.csv" ;;
report)
  src=${2:?FILES_AT}; dest=${3:?results/records/DATE-threads}
  mkdir -p "$dest"; cp "$src/threads.csv" "$src/machine.txt" "$dest/"
  /usr/bin/python3 - "$dest/threads.csv" > "$dest/table.md" <<'PY'
import csv, sys
rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["rc"] == "0"]
one = {(r["tier"], r["method"], r["solver"], r["ordering"]): float(r["init_s"]) for r in rows if r["threads"] == "1"}
print("| vertices | method | solver | ordering | T | init s = build + analyze + factorize | GFlop/s | top phase s (share of flops) | frame ms | init efficiency t(1)/(T t(T)) |")
print("|---|---|---|---|---|---|---|---|---|---|")
for r in rows:
    k = (r["tier"], r["method"], r["solver"], r["ordering"]); T = int(r["threads"]); init = float(r["init_s"])
    eff = f"{one[k] / (T * init):.2f}" if k in one else "-"
    gf = float(r["factor_flops"]) / float(r["factorize_s"]) / 1e9 if float(r["factorize_s"]) > 0 else 0
    top = f"{float(r['factorize_top_s']):.2f} ({float(r['factor_top_flops']) / float(r['factor_flops']):.2f})" if float(r["factor_flops"]) > 0 else "-"
    print(f"| {'104k' if r['tier'] == '1' else '416k'} | {r['method']} | {r['solver']} | {r['ordering']} | {T} | {init:.2f} = {float(r['build_s']):.2f} + "
          f"{float(r['analyze_s']):.2f} + {float(r['factorize_s']):.2f} | {gf:.0f} | {top} | {1e3 * float(r['frame_s']):.1f} | {eff} |")
failed = [r for r in csv.DictReader(open(sys.argv[1])) if r["rc"] != "0"]
if failed: print("\nRuns that failed or timed out: " + "; ".join(f"{r['tier']} {r['method']} {r['solver']} {r['ordering']} T={r['threads']} rc {r['rc']}" for r in failed))
PY
  cat "$dest/table.md" ;;
*) sed -n 2,13p "$0"; exit 1 ;;
esac
