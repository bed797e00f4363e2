#!/usr/bin/env bash
# The project's dissection (graph_ordering.cpp's splits: levels 1, 2 and 4) with its parts ordered by
# METIS_NodeND or by SCOTCH under two strategies of strategies.sh, METIS's default seed (-1) and seeds 1-2; 104k
# and 416k (416k: default seed only), one process at a time. Writes parts.txt (every line) and parts.md here.
# usage: results/records/2026-11-27-scotch-strategies/tuning/parts.sh PATTERN_DIR   (as study.sh)
set -euo pipefail
dir=${1:?PATTERN_DIR}
here=$(cd "$(dirname "$0")" && pwd)
source "$here/strategies.sh"
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
g++ -O2 -o "$t/parts" "$here/parts.cpp" -I"$here/../../2026-11-27-guided-splits-16-cores/tuning" \
  -I/usr/include/suitesparse -I/usr/include/scotch -lcholmod -lmetis -lscotch -lscotcherr -lpthread -lm
run() {  # pattern levels seed
  for k in nodend nd-fm0.5 nd-best2-fm0.5; do
    printf '%s %s ' "$1" "$k" >> "$t/parts.txt"
    "$t/parts" "$dir/$1.bin" "$2" "$3" "${strat[$k]:-nodend}" >> "$t/parts.txt"
  done
}
: > "$t/parts.txt"
for L in 1 2 4; do for s in -1 1 2; do run g104 $L $s; done; done
for L in 1 4; do run g416 $L -1; done
cp "$t/parts.txt" "$here/parts.txt"
/usr/bin/python3 "$here/parts_summary.py" "$here/parts.txt" > "$here/parts.md"
cat "$here/parts.md"
