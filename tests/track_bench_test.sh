#!/usr/bin/env bash
# The Google Benchmark suite through the one gate (python3 -m dbtools.track.bench, `./run track bench`) on the
# real bench_phases, reduced to a few hand-tier benchmarks (--benchmark_filter): a baseline recorded and gated
# against on its exact counters (whether times pass is this machine's noise, not a test: tests/track_gate_test.py
# tests the time rules on synthetic series), a filtered run
# comparing only what ran, a baseline of other suite options or another suite version refused as stale (exit 3),
# one of another CPU as foreign (exit 4; --allow-foreign gates its counters), a counter grown failing, and the
# committed baseline results/bench/baseline.json: of the current suite definition, its counters what the code
# computes now (the hand-tier benchmarks, --allow-foreign: any machine runs this test).
#   track_bench_test.sh SOURCE_DIR BUILD_DIR
set -u
SRC=$(cd "$1" && pwd)
BIN=$(cd "$2" && pwd)
. "$(dirname "$0")/check_lib.sh"  # $T, expect, fail, ok, $fails
cd "$SRC" || exit 1
for f in data/meshes/hand.off data/meshes/armadillo.off; do
  [ -f "$f" ] || { echo "FAIL $f is missing: run scripts/data.sh (./run test does)"; exit 1; }
done
export PYTHONPATH=$SRC/python DEFORMBENCH_BUILD_DIR=$BIN
BENCH=(/usr/bin/python3 -m dbtools.track.bench --min-time 0.01 --runs-dir "$T/runs")
COUNTERS=(--measure n --measure nnz --measure nnz_L --measure bytes)
STEM=mesh:hand/system:lap/build:structured
HAND="--benchmark_filter=^(build|factorize|solve)/$STEM(/backend:(multifrontal|umfpack))?\$"
# edited FILE EXPR: a copy of the record FILE with the Python statement EXPR applied to its dict `d`
edited() {
  /usr/bin/python3 - "$1" "$T/edited.json" "$2" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
exec(sys.argv[3])
json.dump(d, open(sys.argv[2], "w"))
PY
  echo "$T/edited.json"
}
B=$T/base.json
FACT="factorize/mesh:hand/system:lap/build:structured/backend:umfpack"

expect "record a baseline" 0 "baseline updated: $B" -- "${BENCH[@]}" --baseline "$B" --update-baseline -- "$HAND"
[ "$(grep -o '"run_name": "[^"]*"' "$B" | sort -u | wc -l)" -eq 5 ] && ok "five benchmarks in it" ||
  fail "baseline benchmarks: $(grep -o '"run_name": "[^"]*"' "$B" | sort -u)"
grep -q '"deformbench_suite": "[0-9a-f]\{12\} (80 benchmarks)"' "$B" &&
  grep -q '"deformbench_suite_version": "1"' "$B" &&
  grep -q '"deformbench_build_type": "Release"' "$B" && ok "its suite definition and build type" ||
  fail "no suite definition in $(grep deformbench_ "$B")"
expect "the same benchmarks pass" 0 "verdict: pass" -- "${BENCH[@]}" --baseline "$B" "${COUNTERS[@]}" -- "$HAND"
[ -s "$(ls "$T"/runs/run-*.md | tail -1)" ] && ok "Markdown report beside the run" || fail "no report in $T/runs"
RUN=$(ls "$T"/runs/run-*.json | tail -1)
expect "a filtered run compares what ran" 0 \
  "comparisons: .*not run [0-9]+.*\(not run: in the baseline, not in this run\)" \
  -- "${BENCH[@]}" --baseline "$B" "${COUNTERS[@]}" -- "--benchmark_filter=^$FACT\$"
grep -Eq "MISSING|FAIL" "$T/output" && fail "filtered run: $(cat "$T/output")" || ok "no benchmark left out is a failure"
SUITE="bench_phases v1, [0-9a-f]+"
expect "other suite options: stale" 3 "is stale: suite definition '$SUITE \(80 benchmarks\)' in the baseline, \
'$SUITE \([0-9]+ benchmarks\)' now; 2 cell\(s\) the suite no longer defines: \
factorize/$STEM/backend:multifrontal, solve/" \
  -- "${BENCH[@]}" --baseline "$B" -- --backends umfpack "$HAND"
expect "another suite version: stale" 3 "is stale: suite definition 'bench_phases v0, " -- "${BENCH[@]}" \
  --baseline "$(edited "$B" 'd["context"]["deformbench_suite_version"] = "0"')" --run "$RUN"
expect "another CPU: foreign" 4 \
  "is foreign: CPU Some Other CPU in the baseline, .* now: record a baseline on this machine" \
  -- "${BENCH[@]}" --baseline "$(edited "$B" 'd["context"]["deformbench_cpu"] = "Some Other CPU"')" --run "$RUN"
expect "--allow-foreign: the counters gated" 0 "foreign baseline \(--allow-foreign\): deterministic measures only" \
  -- "${BENCH[@]}" --baseline "$T/edited.json" --run "$RUN" --allow-foreign --all
grep -Eq "^$FACT +cpu_s +cpu .* not gated +other machine" "$T/output" && ok "--allow-foreign: times not gated" ||
  fail "--allow-foreign: $(cat "$T/output")"
expect "nnz_L grown 1%: fails" 1 "^$FACT +nnz_L +deterministic +[0-9]+ +[0-9]+ +1\.01[0-9] +FAIL" -- "${BENCH[@]}" \
  --baseline "$(edited "$B" '[b.update(nnz_L=round(b["nnz_L"] / 1.01)) for b in d["benchmarks"] if "nnz_L" in b]')" \
  --run "$RUN"
expect "unreadable run" 2 "no such file|No such file" -- "${BENCH[@]}" --baseline "$B" --run "$T/none.json"
expect "bad option" 1 "--repetitions and --threads must be >= 1" -- "${BENCH[@]}" --repetitions 0

# The committed baseline is of the current suite, and its counters are what the code computes now (its times are
# this machine's, or another's: not a test).
expect "committed baseline: current" 0 "verdict: pass" -- "${BENCH[@]}" --allow-foreign "${COUNTERS[@]}" -- \
  '--benchmark_filter=mesh:hand/'
grep -Eq "comparisons: not run [0-9]+, ok [0-9]+ \(not run" "$T/output" &&
  ok "committed baseline: every counter of the hand tier equal" ||
  fail "committed baseline: counters changed: $(cat "$T/output")"

if ((fails)); then echo "$fails failure(s)"; exit 1; fi
echo "all passed"
