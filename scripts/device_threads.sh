#!/usr/bin/env bash
# Thread scaling (issue 31 item 4): T = 1 2 4 8 16 on a lent 16-core device machine, or the counts up to this
# machine's cores (mode `local`, which `./run threads` runs); the 104k and 416k armadillo TF and LAP edits (or the
# given ones); multifrontal and CHOLMOD (supernodal); one process per run, each deform row kept whole (its
# provenance, the init split, the frame median, the factorization's flops and serial top phase); the machine's
# dgemm and memory read rates at each T before and after the runs (exp_machine_rates). On a device, three steps:
#   DEVICE_BUNDLE=PATH/device-bundle.sh [BASE_REV=REV] [DIAG_PATCH=scripts/device_timeline.patch] \
#     scripts/device_threads.sh prepare
#                                                # here: bundle build/ with the device tool's bundler (not part of
#                                                # the project) and the 104k mesh into .device/ (git-ignored);
#                                                # BASE_REV: a base build of commit REV, DIAG_PATCH: the diagnostic
#                                                # build, the head with the patch, each built in a scratch worktree
#                                                # (BASE_BINARY, DIAG_BINARY: such builds made by hand instead)
#   run tool: carry [".device"], timeout_s 600, command
#       bash .device/device_threads.sh run       # there: $OUT/threads.csv, rates.csv, failed.csv, machine.txt
#   scripts/device_threads.sh report FILES_AT results/records/DATE-threads   # here: those files, table.md, threads.png
# The device tool returns at most eight files a call: run one mode a call (each writes four to six), or mode
# `session` (timeout_s 600): `team` into $OUT/team (DEADLINE_TEAM, 230 s), then the grid of `run` (DEADLINE_GRID:
# by default what is left of 520 s) packed into $OUT/grid.tgz with both modes' logs; here `report-session FILES_AT
# DIR` tabulates both (DIR/team as report-solves does, DIR/grid as report does).
# The device run starts a run only when its estimated length fits before DEADLINE seconds (default 520), most
# needed first (`grid`): round 1 (104k, 416k multifrontal, 416k CHOLMOD at 16, 8 and 2 threads, TF under the ringnd
# ordering at 8 and 16), then more rounds of the 104k runs for their spread, then 416k CHOLMOD at 4 and 1. A run
# not started is absent from threads.csv, and the report says which keys have fewer rounds. The vertex ordering is
# the default (METIS for TF: one more dissection level per doubling of the threads beyond two) unless `ordering`
# says ringnd.
# Mode `solves` (DEADLINE=150, timeout_s 200) checks a change of the solves against BASE_BINARY in interleaved
# rounds and splits the analysis phase at 8 and 16 threads; mode `factor` (DEADLINE=420, timeout_s 480) checks a
# change of the factorization the same way (the init and its top phase, 104k and 416k); mode `ordering`
# (DEADLINE=170, timeout_s 200) a change of the vertex ordering or the analysis (the TF inits at 16 and 8 threads,
# the analysis split at 16); `report-solves FILES_AT DIR` tabulates any of them; mode `team` (DEADLINE=430,
# timeout_s 500) checks the solves and the factorization at once with the 16-core targets. Every row carries the
# whole command's wall time (command_s), which `report-solves` sets beside the init: with BASE_BINARY a build
# before a658a5e it shows what the memory check that ordered the graph once more cost on 16 cores. With
# DIAG_PATCH at prepare (scripts/device_timeline.patch, kept applying to the head by tests/device_patch_test.sh:
# each step's wall and CPU time and page faults, the factorization's top fronts with their teams, and each top
# front's steps; scripts/analysis_timeline.py names the patches for older builds), `team` and `ordering` also run
# it once on the 104k and 416k TF edits at 16 threads, time allowing, into timeline.txt: the analysis step by
# step, which `report-solves` tabulates (timeline.md).
set -euo pipefail
mode=${1:-}
setup() {  # the libraries (a bundle's), the working folder, the meshes, the edits, machine.txt
  D=${BUNDLE:-$PWD/.device}; O=${OUT:?OUT is the device tool\'s output folder}
  if [ -d "$D/lib" ]; then
    for l in libblas.so.3 liblapack.so.3; do ldconfig -p | grep -q "$l " || cp "$D/fallback/$l" "$D/lib/"; done
    export LD_LIBRARY_PATH=$D/lib
  fi
  deadline=$((SECONDS + ${DEADLINE:-520}))
  W=$(mktemp -d); cd "$W"
  { uname -a; nproc; cat /sys/fs/cgroup/cpu.max; lscpu | head -30; head -3 /proc/meminfo; cat /proc/loadavg
    ldd "$D/bin/deformbench" | grep -E "not found|blas|lapack"; } > "$O/machine.txt" 2>&1 || true
  echo "binary,tier,round,method,solver,threads,ordering,rc" > "$O/failed.csv"
  if [ -n "${EDITS:-}" ]; then  # tiers 1..N: the given edit files (local mode), each run as tier 1 is
    mapfile -t EDIT_FILES <<< "$EDITS"; EDIT_FILES=("" "${EDIT_FILES[@]}")
    SMALL=$(seq -s ' ' 1 $((${#EDIT_FILES[@]} - 1))); LARGE=""
    return
  fi
  # The edit of data/edits/armadillo_loop1_whole.edit on the 104k (tier 1) and 416k (tier 2) meshes
  if [ -f "$D/armadillo_loop1.off.gz" ]; then gunzip -c "$D/armadillo_loop1.off.gz" > armadillo_loop1.off
  else ln -s "$D/armadillo_loop1.off" .; fi
  if [ -e "$D/armadillo_loop2.off" ]; then ln -s "$D/armadillo_loop2.off" .
  else "$D/bin/meshtool" subdivide armadillo_loop1.off armadillo_loop2.off 1 > /dev/null 2>&1 ||
    echo "subdivide failed" >> "$O/machine.txt"; fi
  for k in 1 2; do
    printf 'name = armadillo_loop%s_whole\nmesh = armadillo_loop%s.off\nroi = all\nhandle = nearest:-20.2599,97.1076,-28.8554,100\ntransform = translate:0,10,0\n' $k $k > e$k.edit
  done
  EDIT_FILES=("" e1.edit e2.edit); SMALL=1; LARGE=2
  [ "${QUICK:-0}" = 0 ] || LARGE=""
}
rates() {  # phase T...: exp_machine_rates at each T into rates.csv, the header once
  for T in "${@:2}"; do
    DEFORMBENCH_THREADS=$T OPENBLAS_NUM_THREADS=$T OMP_NUM_THREADS=$T "$D/bin/exp_machine_rates" --csv r.csv >> "$O/machine.txt" 2>&1 || continue
    [ -s "$O/rates.csv" ] || { printf 'phase,'; head -1 r.csv; } > "$O/rates.csv"
    tail -n +2 r.csv | sed "s/^/$1,/" >> "$O/rates.csv"
  done
}
one() {  # binary tier round method solver threads ordering frames estimated_seconds: one deform row into threads.csv,
         # with the whole command's wall time (command_s: the init, the frames and what the command does around them)
  [ $((SECONDS + $9)) -le $deadline ] || return 0
  local rc=0 start; start=$(date +%s.%N)
  DEFORMBENCH_THREADS=$6 OPENBLAS_NUM_THREADS=${BLAS_THREADS:-$6} OMP_NUM_THREADS=$6 timeout "${RUN_TIMEOUT:-150}" "$D/bin/$1" deform "${EDIT_FILES[$2]}" \
    --method "$4" --constraints soft --frames "$8" --solver "$5" --ordering "$7" --out o.ply --csv o.csv > log 2>&1 &
  wait $! || rc=$?  # in the background: a signal's trap runs at once, not after the run
  local wall; wall=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.3f", b - a }')  # the whole command
  if [ $rc -eq 0 ]; then
    [ -s "$O/threads.csv" ] || { printf 'binary,tier,round,threads,ordering,command_s,'; head -1 o.csv; } > "$O/threads.csv"
    tail -n +2 o.csv | sed "s/^/$1,$2,$3,$6,$7,$wall,/" >> "$O/threads.csv"
  else
    echo "$1,$2,$3,$4,$5,$6,$7,$rc" >> "$O/failed.csv"; { echo "$*: rc $rc"; tail -3 log; } >> "$O/machine.txt"
  fi
}
timeline() {  # T: the diagnostic build's analysis timeline of the 104k and 416k TF edits at T threads, time allowing
  [ -x "$D/bin/deformbench_diag" ] || return 0
  for k in 1 2; do
    [ $((SECONDS + 20 * k)) -le $deadline ] || return 0
    echo "# e$k, $1 threads" >> "$O/timeline.txt"
    DEFORMBENCH_THREADS=$1 OPENBLAS_NUM_THREADS=$1 OMP_NUM_THREADS=$1 timeout 120 "$D/bin/deformbench_diag" deform "${EDIT_FILES[$k]}" \
      --method tf --constraints soft --frames 1 --out o.ply 2>&1 >/dev/null | grep '^TIMELINE' >> "$O/timeline.txt" || true
  done
}
small() {  # round solvers...: the small tiers' runs (the 104k edit, or every given edit) at every thread count
  local k T S M
  for k in $SMALL; do for T in $TS; do for S in "${@:2}"; do for M in tf lap; do
    one deformbench "$k" "$1" $M "$S" "$T" default 5 15; done; done; done; done
}
large_cholmod() {  # first|rest estimated_seconds: CHOLMOD on the large tier, first at the two largest thread
                   # counts and at 2, then at the rest
  local T M picked
  for T in $DESC; do
    case " $TOP 2 " in *" $T "*) picked=first ;; *) picked=rest ;; esac
    [ "$picked" = "$1" ] || continue
    for M in tf lap; do one deformbench "$LARGE" 1 $M cholmod_supernodal "$T" default 5 "$2"; done
  done
}
grid() {  # the scaling runs at the thread counts TS (ascending), most needed first: round 1 (the small tiers, the
          # large tier's multifrontal runs, its CHOLMOD runs at the two largest counts and 2, TF under the ringnd
          # ordering at the two largest counts), then more rounds of the small tiers for their spread (ROUNDS, 3),
          # then the large tier's other CHOLMOD runs
  local T M k r
  DESC=$(printf '%s\n' $TS | sort -rn | tr '\n' ' '); TOP=$(echo $DESC | cut -d' ' -f1-2)
  rates before $TS
  small 1 multifrontal cholmod_supernodal
  if [ -n "$LARGE" ]; then
    for T in $DESC; do for M in tf lap; do one deformbench "$LARGE" 1 $M multifrontal "$T" default 5 60; done; done
    large_cholmod first 60
  fi
  # The 1-ring dissection (ringnd: every level on threads, the same ordering for every thread count) beside METIS's
  # (one more level per doubling of the threads): the analysis on many cores by both.
  for k in $SMALL $LARGE; do for T in $TOP; do one deformbench "$k" 1 tf multifrontal "$T" ringnd 5 $((k * 25)); done; done
  for r in $(seq 2 "${ROUNDS:-3}"); do
    small "$r" multifrontal $([ "$r" != 2 ] || echo cholmod_supernodal)
    [ "$r" != 2 ] || [ -z "$LARGE" ] || large_cholmod rest 90
  done
  [ "${ROUNDS:-3}" -ge 2 ] || [ -z "$LARGE" ] || large_cholmod rest 90
  rates after $(printf '%s\n' 1 "${DESC%% *}" | sort -un)
}
build_at() {  # REV PATCH DEST: deformbench built at the commit REV (PATCH applied, if not empty) in a scratch
              # worktree, removed afterwards, and copied to DEST
  local w ok=0; w=$(mktemp -d)
  git worktree add -q --detach "$w" "$1" || { rmdir "$w"; echo "no commit $1 to build" >&2; exit 1; }
  { [ -z "$2" ] || git -C "$w" apply "$PWD/$2"; } &&
    cmake -S "$w" -B "$w/build" -DCMAKE_BUILD_TYPE=Release -DDEFORMBENCH_BUILD_TESTS=OFF \
      -DDEFORMBENCH_BUILD_BENCH=OFF > "$w.log" 2>&1 &&
    cmake --build "$w/build" -j "$(nproc)" --target deformbench >> "$w.log" 2>&1 &&
    cp "$w/build/deformbench" "$3" || ok=$?
  git worktree remove --force "$w"
  [ ! -s "$w.log" ] || [ $ok -eq 0 ] || tail -20 "$w.log"
  rm -f "$w.log"
  [ $ok -eq 0 ] || { echo "building $1 ${2:+with $2 }failed" >&2; exit 1; }
}
local_cleanup() {  # mode local's exit: the runs stopped, the scratch gone, DEST the new results or the earlier ones
  kill $(jobs -p) 2>/dev/null || true
  wait || true
  rm -rf "$BUNDLE" "$OUT" "${W:-}"
  if [ -e "$dest" ]; then rm -rf "$OUT.prev"; elif [ -e "$OUT.prev" ]; then mv "$OUT.prev" "$dest"; fi
}
case $mode in
prepare)
  "${DEVICE_BUNDLE:?DEVICE_BUNDLE names the device-bundle.sh of the device tool library}" build .device deformbench meshtool \
    exp_machine_rates exp_analysis
  # The reference BLAS and LAPACK sonames are Debian's OpenBLAS too: set aside, used there only where the machine
  # has none, so that one OpenBLAS (the machine's) serves every library.
  mkdir -p .device/fallback; mv .device/lib/libblas.so.3 .device/lib/liblapack.so.3 .device/fallback/ 2>/dev/null || true
  [ -z "${BASE_REV:-}" ] || build_at "$BASE_REV" "" .device/bin/deformbench_base
  [ -z "${DIAG_PATCH:-}" ] || build_at HEAD "$DIAG_PATCH" .device/bin/deformbench_diag
  [ -z "${BASE_BINARY:-}" ] || cp "$BASE_BINARY" .device/bin/deformbench_base
  [ -z "${DIAG_BINARY:-}" ] || cp "$DIAG_BINARY" .device/bin/deformbench_diag
  gzip -c data/generated/armadillo_loop1.off > .device/armadillo_loop1.off.gz
  cp "$0" .device/device_threads.sh
  du -sh .device ;;
run)
  setup
  TS=${THREADS:-1 2 4 8 16}
  grid
  cat "$O/failed.csv" ;;
local)
  # Here (./run threads, docs/experiments.md): the same grid on this machine with the build in BUILD (default
  # build/), into DEST, which is replaced only when the grid has run (an interrupted or failed run leaves it as it
  # was, and no scratch); then its table and figure. THREADS: the counts (default 1, 2, 4, ... up to the hardware
  # threads, and that count); ROUNDS (3); QUICK=1: the 104k edit only; EDITS: edit files, one a line, instead of the
  # armadillo edits. No deadline. Exit 5 when a run failed (its row in failed.csv, the others kept), as the
  # experiment drivers do.
  dest=$(realpath -m "${2:?DEST}"); here=$(cd "$(dirname "$0")" && pwd); root=$(dirname "$here")
  n=$(nproc); TS=${THREADS:-$( (T=1; while [ $T -lt "$n" ]; do echo $T; T=$((T * 2)); done; echo "$n") | tr '\n' ' ')}
  EDITS=$(while read -r e; do [ -z "$e" ] || realpath -m "$e"; done <<< "${EDITS:-}")  # setup works in a scratch folder
  mkdir -p "$(dirname "$dest")"
  BUNDLE=$(mktemp -d); OUT=$(mktemp -d "$(dirname "$dest")/.threads.XXXXXX")
  trap local_cleanup EXIT; trap 'exit 130' INT; trap 'exit 143' TERM
  ln -s "$(realpath "${BUILD:-$root/build}")" "$BUNDLE/bin"
  for k in 1 2; do
    f=$root/data/generated/armadillo_loop$k.off; [ ! -f "$f" ] || ln -s "$f" "$BUNDLE/"
  done
  DEADLINE=${DEADLINE:-1000000000} RUN_TIMEOUT=${RUN_TIMEOUT:-3600}
  setup
  grid
  [ -s "$OUT/threads.csv" ] ||
    { echo "no run succeeded ($dest left as it was):" >&2; cat "$OUT/machine.txt" >&2; exit 5; }
  "${PY:-/usr/bin/python3}" "$here/device_threads_report.py" "$OUT" > /dev/null
  chmod 755 "$OUT"; [ ! -e "$dest" ] || mv "$dest" "$OUT.prev"; mv "$OUT" "$dest"
  failed=$(($(wc -l < "$dest/failed.csv") - 1))
  echo "thread scaling at T = ${TS% }: $dest/table.md, $dest/threads.png ($failed failed runs)"
  [ "$failed" = 0 ] || exit 5 ;;
solves)
  # A change checked against the build before it (BASE_BINARY at prepare: .device/bin/deformbench_base), in
  # interleaved rounds: the 104k TF and LAP full frames (20 a run) at 4, 8 and 16 threads; then the analysis
  # phase's split (vertex ordering, symbolic analysis) of the 104k and 416k TF edits at 8 and 16 threads.
  setup
  for r in 1 2 3; do for T in 16 8 4; do for M in lap tf; do for B in deformbench_base deformbench; do
    one $B 1 $r $M multifrontal $T default 20 8; done; done; done; done
  for T in 16 8; do
    [ $((SECONDS + 30)) -le $deadline ] || break
    DEFORMBENCH_THREADS=$T OPENBLAS_NUM_THREADS=$T "$D/bin/exp_analysis" --edit e1.edit --edit e2.edit --system tf \
      --orderings metis,ringnd --rounds 2 --csv "$O/analysis_$T.csv" >> "$O/machine.txt" 2>&1 || echo "exp_analysis T=$T failed" >> "$O/machine.txt"
  done
  cat "$O/failed.csv" ;;
factor)
  # A change of the factorization checked against BASE_BINARY in interleaved rounds: the 104k TF and LAP inits at
  # 16, 8 and 4 threads (three rounds), then the 416k TF init at 16 and 8 (two); the machine's rates first.
  setup
  rates before 1 16
  for r in 1 2 3; do for T in 16 8 4; do for M in tf lap; do for B in deformbench_base deformbench; do
    one $B 1 $r $M multifrontal $T default 3 8; done; done; done; done
  for r in 1 2; do for T in 16 8; do for B in deformbench_base deformbench; do
    one $B 2 $r tf multifrontal $T default 3 30; done; done; done
  cat "$O/failed.csv" ;;
team)
  # The top phase on a team (factorization and solves) checked against BASE_BINARY in interleaved rounds, with the
  # issue's 16-core targets: the 104k TF and LAP runs (init and 20 frames) at 16, 8 and 4 threads, the 416k TF
  # init at 16 and 8, the analysis split at 16 threads; the machine's rates first. ROUNDS rounds (3), the two
  # builds' order alternating from round to round, each run only when it fits before DEADLINE.
  setup
  rates before 1 16
  for r in $(seq 1 "${ROUNDS:-3}"); do
    pair="deformbench_base deformbench"; [ $((r % 2)) = 1 ] || pair="deformbench deformbench_base"
    for T in 16 8 4; do for M in tf lap; do for B in $pair; do
      one $B 1 $r $M multifrontal $T default 20 8; done; done; done
    for T in 16 8; do for B in $pair; do one $B 2 $r tf multifrontal $T default 3 30; done; done
    [ "$r" != 1 ] || [ $((SECONDS + 40)) -gt $deadline ] || DEFORMBENCH_THREADS=16 OPENBLAS_NUM_THREADS=16 \
      "$D/bin/exp_analysis" --edit e1.edit --edit e2.edit --system tf --orderings metis,ringnd --rounds 2 \
      --csv "$O/analysis_16.csv" >> "$O/machine.txt" 2>&1 || true
    [ "$r" != 1 ] || timeline 16
  done
  cat "$O/failed.csv" ;;
ordering)
  # A change of the vertex ordering or the analysis checked against BASE_BINARY in interleaved rounds (the order of
  # the two binaries alternating): the 104k and 416k TF inits (3 frames) at 16 and 8 threads, up to four rounds;
  # after the first, the analysis split at 16 threads (exp_analysis: with and without the ordering's tree, paired)
  # and the diagnostic build's analysis timeline at 16 threads. DEADLINE=170, timeout_s 200.
  setup
  rates before 16
  for r in 1 2 3 4; do
    pair="deformbench_base deformbench"; [ $((r % 2)) = 1 ] || pair="deformbench deformbench_base"
    for k in 1 2; do for T in 16 8; do for B in $pair; do one $B $k $r tf multifrontal $T default 3 $((k * 5)); done; done; done
    [ "$r" != 1 ] || [ $((SECONDS + 20)) -gt $deadline ] || DEFORMBENCH_THREADS=16 OPENBLAS_NUM_THREADS=16 \
      "$D/bin/exp_analysis" --edit e1.edit --edit e2.edit --system tf --orderings metis --rounds 2 \
      --csv "$O/analysis_16.csv" >> "$O/machine.txt" 2>&1 || true
    [ "$r" != 1 ] || timeline 16
  done
  cat "$O/failed.csv" ;;
report)
  src=${2:?FILES_AT}; dest=${3:?results/records/DATE-threads}
  mkdir -p "$dest"; for f in threads.csv rates.csv failed.csv machine.txt; do cp "$src/$f" "$dest/"; done
  /usr/bin/python3 "$(dirname "$0")/device_threads_report.py" "$dest" ;;
blas)
  # Whether the BLAS's own threads (OpenBLAS's pool, sized at start) slow the solves of a plan for fewer threads:
  # the 104k TF and LAP frames at 16 threads with 16, 8 and 1 BLAS threads and at 8 threads, interleaved rounds.
  setup
  for r in 1 2 3; do for M in lap tf; do for cfg in 16:16 16:8 16:1 8:8; do
    BLAS_THREADS=${cfg#*:} one deformbench 1 $r $M multifrontal ${cfg%:*} default 20 6; done; done; done
  cat "$O/failed.csv" ;;
session)
  base=${OUT:?OUT is the device tool\'s output folder}; g=$(mktemp -d); mkdir -p "$base/team" "$g/grid"
  OUT=$base/team DEADLINE=${DEADLINE_TEAM:-230} bash "$0" team > "$g/team.log" 2>&1 || echo "team: rc $?"
  OUT=$g/grid DEADLINE=${DEADLINE_GRID:-$((520 - SECONDS))} bash "$0" run > "$g/grid.log" 2>&1 || echo "grid: rc $?"
  cp "$g/team.log" "$g/grid.log" "$g/grid/"; tar czf "$base/grid.tgz" -C "$g" grid
  tail -n 3 "$g/team.log" "$g/grid.log"; rm -rf "$g" ;;
report-session)
  src=${2:?FILES_AT}; dest=${3:?DIR}; g=$(mktemp -d)
  tar xzf "$src/grid.tgz" -C "$g"
  "$0" report-solves "$src/team" "$dest/team" && "$0" report "$g/grid" "$dest/grid"; rc=$?
  rm -rf "$g"; exit $rc ;;
report-solves)
  src=${2:?FILES_AT}; dest=${3:?DIR}
  mkdir -p "$dest"; cp "$src"/*.csv "$src/machine.txt" "$dest/"
  if [ -s "$src/timeline.txt" ]; then
    cp "$src/timeline.txt" "$dest/"
    /usr/bin/python3 "$(dirname "$0")/analysis_timeline.py" "$dest/timeline.txt" > "$dest/timeline.md"
  fi
  /usr/bin/python3 "$(dirname "$0")/device_threads_report.py" --solves "$dest" ;;
*) sed -n '2,/^set -euo/p' "$0" | sed '$d'; exit 1 ;;
esac
