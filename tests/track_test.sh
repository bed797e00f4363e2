#!/usr/bin/env bash
# The tracking suite end to end on the real driver (build/exp_track), reduced to small meshes (hand and the CGAL
# cactus of the data step; it fails naming them when they are missing): strict command line and config, the
# shipped suite's grid, and a planted regression:
# the suite run again through the driver (python3 -m dbtools.track) with a worse ordering for the TF cells (--override ordering=natural)
# against a baseline with the default fails, naming nnz(L) and factor bytes of the TF cells and nothing of LAP's;
# the same worse ordering caught by the CPU-time rule alone (init_cpu_s); the unchanged cell is gated on its exact
# measures only (whether it passes on time is the machine's noise: results/history/README.md).
#   track_test.sh SOURCE_DIR BUILD_DIR
set -u
SRC=$(cd "$1" && pwd)
BIN=$(cd "$2" && pwd)
. "$(dirname "$0")/check_lib.sh"  # $T, expect, fail, ok, $fails
cd "$SRC" || exit 1
X="$BIN/exp_track"
export PYTHONPATH=$SRC/python

# ---------------------------------------------------------------- command line and the shipped suite
expect "--help" 0 "Usage: exp_track" -- "$X" --help
expect "misspelled option" 1 "did you mean --repeats" -- "$X" --repeat 3
expect "the shipped suite" 0 "^solve/armadillo/lap/spqr/default " -- "$X" --dry-run
[ "$(grep -c . "$T/output")" -eq 29 ] && ok "29 cells in the shipped suite" || fail "shipped suite: $(grep -c . "$T/output") cells"
grep -Eq "^deform/armadillo_loop1/tf/structured/multifrontal .* rounds=2$" "$T/output" &&
  grep -Eq "^solve/armadillo/lap/umfpack/default .* rounds=5$" "$T/output" &&
  grep -Eq "^deform/hand/tf/naive/multifrontal .* rounds=10$" "$T/output" && ok "rounds per cell" || fail "rounds: $(cat "$T/output")"
expect "--only" 0 "^deform/hand/tf/naive/multifrontal +kind=deform model=hand method=tf build=naive .*frames=5" -- \
  "$X" --dry-run --only 'deform/hand/tf/*'
expect "--only matching nothing" 1 "no cell to run" -- "$X" --dry-run --only 'nothing*'
expect "override recorded in the spec" 0 "deform/hand/tf/structured/multifrontal .*ordering=natural" -- \
  "$X" --dry-run --only 'deform/hand/tf/*' --override "kind=deform method=tf: ordering=natural"
expect "malformed pattern" 1 "cell pattern 'deform hand method=lap': no ':'" -- "$X" --dry-run --cells "deform hand method=lap"
expect "unknown tier" 1 "no tier 'horse'" -- "$X" --dry-run --cells "deform horse: method=lap"
expect "misspelled cell key" 1 "methd" -- "$X" --dry-run --cells "deform hand: methd=lap"
expect "unknown backend" 1 "cholmod" -- "$X" --dry-run --cells "solve hand: backend=cholmod"
expect "a cell twice" 1 "listed twice" -- "$X" --dry-run --cells "deform hand: method=lap" --cells "deform hand: method=lap"
printf 'bogus = 1\n' >"$T/bad.toml"
expect "unknown config key" 1 "bogus" -- "$X" --config "$T/bad.toml" --dry-run
expect "unwritable history" 1 "not a directory|does not exist" -- "$X" --out "$T/no/such/h.csv" --only 'deform/hand/lap/s*'
expect "--machine-id" 0 "^[0-9a-f]{12}$" -- "$X" --machine-id

# ---------------------------------------------------------------- a planted regression, end to end
for f in data/meshes/hand.off data/meshes/cactus.off; do
  [ -f "$f" ] || { echo "FAIL $f is missing: run scripts/data.sh (./run test does)"; exit 1; }
done
cat >"$T/small.toml" <<'EOF'
tier = ["hand=meshes/hand.off", "cactus=meshes/cactus.off"]
cells = ["deform hand,cactus: method=lap,tf build=structured"]
default = ["kind=deform: constraints=soft frames=2"]
repeats = 1
EOF
expect "baseline run" 0 "wrote" -- "$X" --config "$T/small.toml" --data "$SRC/data" --out "$T/base.csv"
# A cell made to fail (killed at its timeout): the history is written with its status row, the run exits 5.
expect "a failed cell" 5 "FAILED kind=deform model=cactus method=tf .*frames=100000" -- "$X" --config "$T/small.toml" \
  --data "$SRC/data" --out "$T/failed.csv" --only 'deform/cactus/tf/*' --override "kind=deform: frames=100000" \
  --cell-timeout-s 1
grep -q ",status,.*timed out" "$T/failed.csv" && ok "the failed cell's status row" || fail "no status row: $(cat "$T/failed.csv")"
[ "$(cut -d, -f4 "$T/base.csv" | sort -u | grep -c /)" -eq 4 ] && ok "four cells in the history" || fail "cells: $(cut -d, -f4 "$T/base.csv" | sort -u)"
# One repeat a side: these small cells' peak RSS moves a few percent between runs, near the gate's default 5%; this
# part tests the exact measures' rule (the RSS rule on real runs: results/records/2026-11-26-gate-false-alarms).
TRACK=(env DEFORMBENCH_BUILD_DIR="$BIN" /usr/bin/python3 -m dbtools.track --no-build --no-plots
  --config "$T/small.toml" --history-dir "$T/history" --report "$T/track.md" --baseline-file "$T/base.csv"
  --rss-threshold 20)
expect "same suite passes" 0 "verdict: pass" -- "${TRACK[@]}"
expect "TF with the natural ordering fails" 1 "verdict: FAIL" -- "${TRACK[@]}" \
  --override "kind=deform method=tf: ordering=natural"
for tier in hand cactus; do
  for m in nnz_factor factor_bytes; do
    grep -Eq "^deform/$tier/tf/structured/multifrontal +$m +deterministic +[0-9]+ +[0-9]+ +[0-9.]+ +FAIL" "$T/output" &&
      ok "names $tier tf $m" || fail "$tier tf $m not named: $(cat "$T/output")"
  done
done
grep -E "^deform/[a-z]+/lap/.*FAIL" "$T/output" && fail "a lap cell failed" || ok "lap cells unchanged"
grep -q "| deform/cactus/tf/structured/multifrontal | nnz_factor | deterministic |" "$T/track.md" &&
  ok "Markdown report names it" || fail "track.md: $(head -20 "$T/track.md")"
# The default: two runs an invocation (--runs 2), each its own history file with its JSON beside it.
[ "$(ls "$T/history/runs"/*.csv | wc -l)" -eq 4 ] && [ "$(ls "$T/history/runs"/*.json | wc -l)" -eq 4 ] &&
  ok "one history file per run, two runs an invocation, its JSON beside it" || fail "histories: $(ls "$T/history/runs")"
grep -q "^runs a side: 2 run(s) now, 1 run(s) in the baseline" "$T/output" && ok "the report names the sides" ||
  fail "sides: $(cat "$T/output")"

# A planted slowdown caught by the CPU-time rule alone (--measure init_cpu_s): the TF cell of hand in 5 rounds, run
# twice unchanged; the second run gated on its exact measures, and a copy of the first with every round's init CPU
# time raised by twice the largest of them (at least 3x, and slower than every round of the original whatever the
# machine's noise: a test of the rule, not of this machine's timing; the gate's power on real runs is measured in
# results/records/2026-11-26-gate-false-alarms).
cat >"$T/cpu.toml" <<'EOF'
tier = ["hand=meshes/hand.off"]
cells = ["deform hand: method=tf build=structured"]
default = ["kind=deform: constraints=soft frames=2"]
repeats = 5
EOF
for run in base same; do
  "$X" --config "$T/cpu.toml" --data "$SRC/data" --out "$T/cpu_$run.csv" >/dev/null 2>&1 || fail "cpu run $run did not run"
done
/usr/bin/python3 - "$T/cpu_base.csv" "$T/cpu_slow.csv" <<'PY' || fail "could not plant the slowdown"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1], newline="")))
init = [r for r in rows if r["measure"] == "init_cpu_s" and r["class"] != "status" and r["value"]]
top = max(float(r["value"]) for r in init)
for r in init:
    r["value"] = repr(float(r["value"]) + 2 * top)
with open(sys.argv[2], "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(rows[0]))
    w.writeheader()
    w.writerows(rows)
PY
GATE=(/usr/bin/python3 -m dbtools.track.gate --measure init_cpu_s "$T/cpu_base.csv")
expect "unchanged: exact measures pass" 0 "verdict: pass" -- \
  /usr/bin/python3 -m dbtools.track.gate --measure nnz_factor "$T/cpu_base.csv" "$T/cpu_same.csv"
expect "CPU time: a slower init fails" 1 \
  "^deform/hand/tf/structured/multifrontal +init_cpu_s +cpu +[0-9.]+ +[0-9.]+ +[0-9.]+ +0.00[0-9]+ +FAIL" -- \
  "${GATE[@]}" "$T/cpu_slow.csv"

# The trend view of these histories: the runs with overrides are left out, the two others (one commit, in a row) are
# one point, which is no trend: no figure. A copy of a run as another, later commit's makes two points and every
# figure.
mkdir -p "$T/plots" && : >"$T/plots/history_init.png"
expect "trend view: one point" 0 "one point of machine [0-9a-f]{12} .*no trend figure" -- \
  env PYTHONPATH="$SRC/python" PYTHONDONTWRITEBYTECODE=1 /usr/bin/python3 -m dbtools.plots.history --results "$T" --out "$T/plots"
[ -e "$T/plots/history_init.png" ] && fail "an earlier trend figure left beside one point" || ok "no trend figure"
/usr/bin/python3 - "$(ls "$T"/history/runs/*.csv | head -1)" "$T/history/runs/zz_next_commit.csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1], newline="")))
for r in rows:
    r.update(git_sha="0123456789ab", commit="0123456789ab" * 3, date="2999-01-01T00:00:00Z")
with open(sys.argv[2], "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(rows[0]))
    w.writeheader()
    w.writerows(rows)
PY
expect "trend view" 0 "3 run\(s\) of machine [0-9a-f]{12} as 2 point\(s\) .*-> $T/plots/history_\*.png" -- \
  env PYTHONPATH="$SRC/python" PYTHONDONTWRITEBYTECODE=1 /usr/bin/python3 -m dbtools.plots.history --results "$T" --out "$T/plots"
for f in init frame factor_bytes peak_rss; do
  [ -s "$T/plots/history_$f.png" ] && ok "history_$f.png" || fail "no history_$f.png"
done
expect "trend view: unknown machine" 1 "no history of machine nosuch" -- \
  env PYTHONPATH="$SRC/python" PYTHONDONTWRITEBYTECODE=1 /usr/bin/python3 -m dbtools.plots.history --results "$T" --out "$T/plots" --machine nosuch
expect "trend view: no history" 0 "no history under" -- \
  env PYTHONPATH="$SRC/python" PYTHONDONTWRITEBYTECODE=1 /usr/bin/python3 -m dbtools.plots.history --results "$T/none" --out "$T/plots"

if ((fails)); then echo "$fails failure(s)"; exit 1; fi
echo "all passed"
