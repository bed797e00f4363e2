#!/usr/bin/env bash
# SIGINT and SIGTERM (and, while a mesh is written, SIGHUP and SIGPIPE) mid-run leave nothing behind
# (solvers/base/cleanup.h; docs/cli.md, exit codes): sent to
# `deformbench deform --solver mumps --factor-dir DIR` mid-solve (one process, and 2 ranks under mpirun), to
# `meshtool convert` while it writes the mesh, to `advise` and `advise --calibrate` while a child runs, and to an
# experiment driver while its cell runs. Each must exit 128 + the signal's number, 130 for SIGINT and 143 for
# SIGTERM (under mpirun: the launcher's own non-zero code), leave no MUMPS file and no staged
# `*.tmp.PID*` temporary, leave the earlier outputs byte for byte as they were, and leave no child running.
# Every signal is sent once the process is seen in the phase (polling for its scratch file, or its child), never
# after a fixed sleep, so a loaded machine only makes the test slower.
#   signals_test.sh SOURCE_DIR BUILD_DIR
set -u
SRC=$1
BIN=$2
. "$(dirname "$0")/check_lib.sh"  # $T, fail, ok, $fails
cd "$SRC" || exit 1
set -m  # background jobs get SIGINT (a non-interactive shell's background jobs otherwise ignore it)
export OPENBLAS_NUM_THREADS=1
EDIT=data/edits/armadillo_whole.edit
BIG=data/generated/armadillo_loop1.off  # large enough that writing it takes a while
[ -f "$BIG" ] || BIG=data/meshes/armadillo.off

# until SECONDS_MAX CMD...: polls CMD every 20 ms; false after SECONDS_MAX seconds.
until_true() {
  local end=$((SECONDS + $1))
  shift
  while ! "$@"; do
    ((SECONDS < end)) || return 1
    sleep 0.02
  done
}
files_in() { [ "$(find "$1" -maxdepth 1 -type f -name "$2" | wc -l)" -ge "$3" ]; }
no_files_in() { [ -z "$(find "$1" -mindepth 1 -maxdepth 1 -name "$2")" ]; }
# gone PID: not running (no such process, or a zombie: dead, its parent gone before reaping it)
gone() { local st; st=$(ps -o stat= -p "$1" 2>/dev/null); [ -z "$st" ] || [ "${st:0:1}" = Z ]; }
# wait_exit PID: its exit status. A wait that returns 128 + SIGSTOP (the job was seen stopped; bash may report that
# again until it sees the job continue) is repeated.
wait_exit() {
  local rc stopped=$((128 + $(kill -l STOP))) try
  for try in $(seq 200); do
    wait "$1"
    rc=$?
    [ $rc -eq $stopped ] || return $rc
    kill -CONT "$1" 2>/dev/null
    sleep 0.05
  done
  return $rc
}
# never_reached PID MESSAGE: the run never reached the phase: a failure, and the run is ended.
never_reached() {
  fail "$2: $(tail -c 300 "$T/log")"
  kill -KILL "$1" 2>/dev/null
  wait "$1"
}
# exits_with SIG RC NAME: RC is SIG's documented exit code.
exits_with() {
  [ "$2" -eq "$(code_of "$1")" ] && ok "$3: exit $2" || fail "$3: exit $2, not $(code_of "$1") $(tail -c 300 "$T/log")"
}
code_of() { echo $((128 + $(kill -l "$1"))); }

# Earlier outputs in $T/out, kept in $T/before to compare with.
earlier_outputs() {
  rm -rf "$T/out" "$T/before"
  mkdir -p "$T/out" "$T/before"
  for f in "$@"; do echo "earlier $f" >"$T/out/$f"; done
  cp -p "$T"/out/* "$T/before/"
}
unchanged() {
  diff -r "$T/before" "$T/out" >/dev/null && ok "$1: earlier outputs unchanged, no temporary left" ||
    fail "$1: outputs changed or left: $(ls "$T/out")"
}

# ---------------------------------------------------------------- mid-solve, MUMPS out of core
for sig in INT TERM; do
  earlier_outputs a.off a.csv
  rm -rf "$T/fd" && mkdir -p "$T/fd"
  "$BIN/deformbench" deform $EDIT --solver mumps --factor-dir "$T/fd" --frames 100000 --out "$T/out/a.off" \
    --csv "$T/out/a.csv" >"$T/log" 2>&1 &
  pid=$!
  if until_true 300 files_in "$T/fd" 'deformbench-mumps*' 1; then
    kill -$sig $pid
    wait $pid
    rc=$?
    exits_with $sig $rc "deform SIG$sig mid-solve"
    no_files_in "$T/fd" '*' && ok "deform SIG$sig: no MUMPS file left" || fail "deform SIG$sig: left $(ls "$T/fd")"
    unchanged "deform SIG$sig"
  else
    never_reached $pid "deform SIG$sig: no MUMPS file appeared"
  fi
done

# ---------------------------------------------------------------- advise and its calibration mid-run
# Their scratch (TMPDIR/deformbench-NAME-PID-*: edits, children's outputs) is removed, the calibration file is not
# written, and the child deform they were waiting on ends too.
mkdir -p "$T/tmp"
for sig in INT TERM; do
  for what in advise calibrate; do
    earlier_outputs cal.csv
    rm -rf "$T/tmp"/*
    if [ $what = advise ]; then set -- advise $EDIT --quick --backends multifrontal; else set -- advise --calibrate; fi
    TMPDIR=$T/tmp DEFORMBENCH_CALIBRATION=$T/out/cal.csv "$BIN/deformbench" "$@" >"$T/log" 2>&1 &
    pid=$!
    if until_true 300 files_in "$T/tmp" "deformbench-$what-*" 1; then
      kill -$sig $pid
      wait_exit $pid
      exits_with $sig $? "$what SIG$sig"
      until_true 30 no_files_in "$T/tmp" '*' && ok "$what SIG$sig: no scratch left" ||
        fail "$what SIG$sig: left $(ls "$T/tmp")"
      pgrep -f "$T/tmp/deformbench-" >/dev/null && fail "$what SIG$sig: a child still runs" || ok "$what SIG$sig: no child left"
      unchanged "$what SIG$sig"
    else
      never_reached $pid "$what SIG$sig: no scratch file appeared"
    fi
  done
done

# ---------------------------------------------------------------- mid-solve on 2 ranks: every rank cleans up
if command -v "${MPIEXEC:-mpirun}" >/dev/null; then
  earlier_outputs a.off
  rm -rf "$T/fd" && mkdir -p "$T/fd"
  scripts/mpirun.sh 2 "$BIN/deformbench" deform $EDIT --solver mumps --factor-dir "$T/fd" --frames 100000 \
    --out "$T/out/a.off" >"$T/log" 2>&1 &
  pid=$!
  if until_true 300 files_in "$T/fd" 'deformbench-mumps*' 2; then
    kill -TERM $pid
    wait $pid
    rc=$?
    [ $rc -ne 0 ] && ok "2 ranks SIGTERM: mpirun exit $rc" || fail "2 ranks SIGTERM: exit 0"
    until_true 30 no_files_in "$T/fd" '*' && ok "2 ranks SIGTERM: no MUMPS file left on either rank" ||
      fail "2 ranks SIGTERM: left $(ls "$T/fd")"
    unchanged "2 ranks SIGTERM"
  else
    never_reached $pid "2 ranks: no MUMPS files of both ranks appeared"
  fi
fi

# ---------------------------------------------------------------- while the mesh is written
# The temporary exists only while the mesh is written: the process is stopped (SIGSTOP) as soon as it is seen and
# signalled only when it is the one temporary there, so the signal lands mid-write; a run that got past it first is
# tried again. (A run stopped later, with the CSV's temporary beside or instead, may be committing its outputs: a
# signal then waits for the commit to finish, atomic_file.h, and the new outputs are the right result.)
# mid_write SIG NAME OUTPUT CMD...: runs CMD (writing OUTPUT under $T/out) until it is caught writing, then sends SIG.
mid_write() {
  local sig=$1 name=$2 out=$3 caught=0 attempt pid rc
  shift 3
  local stem="$T/out/${out%.*}" whole="$T/out/$out"  # OUTPUT's temporary: staged (NAME.tmp.PID.EXT) or not (OUTPUT.tmp.PID)
  mine() { compgen -G "$stem.tmp.*"; compgen -G "$whole.tmp.*"; }
  for attempt in 1 2 3 4 5; do
    earlier_outputs "$out" a.csv
    "$@" >"$T/log" 2>&1 &
    pid=$!
    until_true 300 eval "[ -n \"\$(compgen -G '$T/out/*.tmp.*')\" ] || ! kill -0 $pid 2>/dev/null"
    kill -STOP $pid 2>/dev/null
    if [ -n "$(mine)" ] && [ "$(compgen -G "$T/out/*.tmp.*")" = "$(mine)" ]; then
      kill -$sig $pid
      kill -CONT $pid
      wait_exit $pid
      rc=$?
      caught=1
      exits_with $sig $rc "$name SIG$sig mid-write"
      unchanged "$name SIG$sig mid-write"
      break
    fi
    kill -CONT $pid 2>/dev/null
    wait_exit $pid
  done
  [ $caught -eq 1 ] || fail "$name SIG$sig: the write was never caught in 5 runs"
}
# SIGHUP (a closed terminal) and SIGPIPE (a reader gone) clean up as SIGINT and SIGTERM do.
for sig in INT TERM HUP PIPE; do
  mid_write $sig meshtool big.obj "$BIN/meshtool" convert "$BIG" "$T/out/big.obj"
done
# deform's mesh and CSV are staged together (the CSV row is written after the mesh)
BIG_EDIT=data/edits/armadillo_loop1_whole.edit
[ -f "$BIG" ] && [ "$BIG" = data/generated/armadillo_loop1.off ] || BIG_EDIT=$EDIT
mid_write INT deform big.obj "$BIN/deformbench" deform $BIG_EDIT --frames 1 --out "$T/out/big.obj" --csv "$T/out/a.csv"

# ---------------------------------------------------------------- a driver with a running cell
for sig in TERM INT; do
  earlier_outputs deform_cases.csv
  "$BIN/exp_deform_cases" --case arm=edits/armadillo_whole.edit --methods lap --frames 100000 \
    --out "$T/out/deform_cases.csv" >"$T/log" 2>&1 &
  pid=$!
  child=""
  find_child() { child=$(pgrep -P $pid -f -- '--cell' | head -1); [ -n "$child" ]; }  # the cell, not a helper
  if until_true 300 find_child; then
    kill -$sig $pid
    wait $pid
    rc=$?
    exits_with $sig $rc "driver SIG$sig with a running cell"
    gone "$child" && ok "driver SIG$sig: its cell $child is not left running" || { fail "driver SIG$sig: cell $child orphaned"; kill -KILL "$child"; }
    unchanged "driver SIG$sig"
  else
    never_reached $pid "driver SIG$sig: no cell started"
  fi
done

((fails == 0)) && echo "signals: all ok" || echo "signals: $fails failure(s)"
exit $((fails > 0))
