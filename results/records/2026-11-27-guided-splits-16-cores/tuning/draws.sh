#!/usr/bin/env bash
# The draws study of the 16-part dissection: draws.cpp (built here into a temporary directory) at four levels on
# the 104k pattern (METIS's default seed -1 and seeds 1-14) and the 416k pattern (-1 and 1-6), both modes per seed,
# the two sizes on two processes at once. Writes draws.txt (every line) and draws.md (draws_summary.py) here.
# usage: results/records/2026-11-27-guided-splits-16-cores/tuning/draws.sh PATTERN_DIR   (PATTERN_DIR holds
#        g104.bin and g416.bin, written by ../../2026-11-26-analysis-levers/tuning/dump_pattern.cpp from
#        data/edits/armadillo_loop1_whole.edit and armadillo_loop2_whole.edit)
set -euo pipefail
dir=${1:?PATTERN_DIR}
here=$(cd "$(dirname "$0")" && pwd)
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
g++ -O2 -o "$t/draws" "$here/draws.cpp" -I/usr/include/suitesparse -lcholmod -lmetis
("$t/draws" "$dir/g104.bin" 4 -1 0; "$t/draws" "$dir/g104.bin" 4 1 15) > "$t/a.txt" &
a=$!
("$t/draws" "$dir/g416.bin" 4 -1 0; "$t/draws" "$dir/g416.bin" 4 1 7) > "$t/b.txt"
wait $a
cat "$t/a.txt" "$t/b.txt" | sed "s#$dir/##" > "$here/draws.txt"
/usr/bin/python3 "$here/draws_summary.py" "$here/draws.txt" > "$here/draws.md"
cat "$here/draws.md"
