#!/usr/bin/env bash
# scripts/bench_compare.sh's gates on an existing run (--run, nothing benchmarked): the baseline against itself
# passes; a run whose nnz_L grew by 1% fails naming it; a run whose bytes shrank is reported and passes; a run
# whose CPU time of one benchmark is 50% longer fails naming it; one whose wall time alone doubled (a loaded
# machine) is reported and passes, and fails with --gate-wall.
#   bench_compare_test.sh SOURCE_DIR
set -u
SRC=$(cd "$1" && pwd)
. "$(dirname "$0")/check_lib.sh"  # $T, fail, ok, $fails
[ -f /usr/share/benchmark/compare.py ] || { echo "FAIL /usr/share/benchmark/compare.py is missing: install libbenchmark-tools (./run does)"; exit 1; }
B=$SRC/results/bench/baseline.json
NAME="factorize/mesh:armadillo/system:tf/build:structured/backend:multifrontal"
# scaled COUNTER FACTOR OUT: the baseline with one benchmark's counter scaled in every entry
scaled() {
  /usr/bin/python3 - "$B" "$NAME" "$1" "$2" "$3" <<'PY'
import json, sys
src, name, counter, factor, out = sys.argv[1:]
d = json.load(open(src))
for b in d["benchmarks"]:
    if b.get("run_name", b["name"]) == name:
        b[counter] = b[counter] * float(factor) if counter.endswith("_time") else round(b[counter] * float(factor))
json.dump(d, open(out, "w"))
PY
}
run() { bash "$SRC/scripts/bench_compare.sh" --baseline "$B" --run "$@" >"$T/out" 2>&1; }

cp "$B" "$T/same.json"
run "$T/same.json" && grep -q "all equal" "$T/out" && ok "baseline against itself" || fail "same: $(tail -5 "$T/out")"
scaled nnz_L 1.01 "$T/grew.json"
run "$T/grew.json"; code=$?
[ $code -eq 1 ] && grep -Eq "GREW +$NAME nnz_L: [0-9]+ -> [0-9]+ \(\+1\.00%\)" "$T/out" && ok "nnz_L +1% fails" ||
  fail "grew: exit $code $(tail -8 "$T/out")"
scaled bytes 0.99 "$T/shrank.json"
run "$T/shrank.json" && grep -Eq "changed +$NAME bytes" "$T/out" && ok "bytes -1% reported, passes" ||
  fail "shrank: $(tail -8 "$T/out")"
scaled cpu_time 1.5 "$T/cpu.json"
run "$T/cpu.json"; code=$?
[ $code -eq 1 ] && grep -Eq "SLOWER +$NAME: .*\(\+50\.0%\)" "$T/out" && grep -q "FAIL: 1 regression" "$T/out" &&
  ok "CPU time +50% fails" || fail "cpu: exit $code $(tail -8 "$T/out")"
scaled real_time 2 "$T/wall.json"
run "$T/wall.json" && grep -Eq "slower +$NAME: .*\(\+100\.0%\)" "$T/out" && ok "wall time x2 reported, passes" ||
  fail "wall: $(tail -8 "$T/out")"
run "$T/wall.json" --gate-wall; code=$?
[ $code -eq 1 ] && grep -Eq "SLOWER +$NAME: .*\(\+100\.0%\)" "$T/out" && ok "--gate-wall: wall time x2 fails" ||
  fail "--gate-wall: exit $code $(tail -8 "$T/out")"
if ((fails)); then echo "$fails failure(s)"; exit 1; fi
echo "all passed"
