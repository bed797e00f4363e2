#!/usr/bin/env bash
# The seeds study: seeds.cpp (built here into a temporary directory) on the 26k, 104k and 416k patterns, both
# modes per seed: METIS's default seed (-1) and 12 seeds at 26k (levels 1-2), 10 at 104k (levels 1-4), 6 at 416k
# (levels 1, 2, 4), the sizes on two processes at once. Writes study.txt (every line) and study.md (summary.py) in
# the record's folder.
# usage: results/records/2026-11-27-guided-splits/tuning/study.sh PATTERN_DIR   (PATTERN_DIR holds g26.bin,
#        g104.bin and g416.bin, written by ../../2026-11-26-analysis-levers/tuning/dump_pattern.cpp from
#        data/edits/armadillo_whole.edit, armadillo_loop1_whole.edit and armadillo_loop2_whole.edit)
set -euo pipefail
dir=${1:?PATTERN_DIR}
here=$(cd "$(dirname "$0")" && pwd)
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
g++ -O2 -o "$t/seeds" "$here/seeds.cpp" -I/usr/include/suitesparse -lcholmod -lmetis
(for L in 1 2; do "$t/seeds" "$dir/g26.bin" $L -1 0; "$t/seeds" "$dir/g26.bin" $L 1 13; done
 for L in 1 2 3 4; do "$t/seeds" "$dir/g104.bin" $L -1 0; "$t/seeds" "$dir/g104.bin" $L 1 11; done) > "$t/a.txt" &
a=$!
for L in 1 2 4; do "$t/seeds" "$dir/g416.bin" $L -1 0; "$t/seeds" "$dir/g416.bin" $L 1 7; done > "$t/b.txt"
wait $a
cat "$t/a.txt" "$t/b.txt" | sed "s#$dir/##" > "$here/../study.txt"
/usr/bin/python3 "$here/summary.py" "$here/../study.txt" > "$here/../study.md"
cat "$here/../study.md"
