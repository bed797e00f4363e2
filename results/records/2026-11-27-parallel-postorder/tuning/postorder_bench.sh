#!/usr/bin/env bash
# The postordering step alone (postorder_bench.cpp, built here against the project's solver library): medians of
# REPEATS runs each of CHOLMOD's analysis and of postorder_dissection on 1 and 2 threads, at 1, 2 and 4 dissection
# levels, on the 26k, 104k and 416k patterns. Writes postorder_bench.txt here.
# usage: results/records/2026-11-27-parallel-postorder/tuning/postorder_bench.sh PATTERN_DIR BUILD_DIR [REPEATS]
#        (PATTERN_DIR as ../../2026-11-27-scotch-strategies/tuning/study.sh's; BUILD_DIR a Release build of the
#        repository holding solvers/libdeformbench_solvers.a)
set -euo pipefail
dir=${1:?PATTERN_DIR} build=${2:?BUILD_DIR} repeats=${3:-7}
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../../.." && pwd)
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
g++ -O2 -std=c++17 -o "$t/bench" "$here/postorder_bench.cpp" -I"$root" \
  -I"$root/results/records/2026-11-27-guided-splits-16-cores/tuning" -I/usr/include/suitesparse \
  "$build/solvers/libdeformbench_solvers.a" -lcholmod -lmetis -lfmt -lpthread
for g in g26 g104 g416; do
  for L in 1 2 4; do "$t/bench" "$dir/$g.bin" $L "$repeats" | sed "s#$dir/##"; done
done | tee "$here/postorder_bench.txt"
