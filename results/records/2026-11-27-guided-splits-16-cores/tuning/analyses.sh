#!/usr/bin/env bash
# The serial CHOLMOD analyses and the two ways to cut them (analyses.cpp, built here into a temporary directory):
# five repetitions on the 104k and the 416k pattern, one process at a time. Writes analyses.txt here.
# usage: results/records/2026-11-27-guided-splits-16-cores/tuning/analyses.sh PATTERN_DIR   (as draws.sh)
set -euo pipefail
dir=${1:?PATTERN_DIR}
here=$(cd "$(dirname "$0")" && pwd)
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
g++ -O2 -o "$t/analyses" "$here/analyses.cpp" -I/usr/include/suitesparse -lcholmod
for g in g104 g416; do "$t/analyses" "$dir/$g.bin"; done | sed "s#$dir/##" > "$here/analyses.txt"
cat "$here/analyses.txt"
