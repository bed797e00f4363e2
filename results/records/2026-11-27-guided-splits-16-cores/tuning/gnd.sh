#!/usr/bin/env bash
# Guided nested dissection all the way down against METIS_NodeND: gnd.cpp (built here into a temporary directory)
# on the 26k and 104k patterns (METIS's default seed -1 and seeds 1-5) and the 416k pattern (-1, 1, 2), one
# process at a time: METIS_NodeND of the whole graph; guided splits to parts of 100, 200, 400 vertices ordered by
# AMD; guided splits to parts of 1000 and 3000 vertices ordered by METIS_NodeND. Writes gnd.txt (every line) and
# gnd.md (gnd_summary.py) here.
# usage: results/records/2026-11-27-guided-splits-16-cores/tuning/gnd.sh PATTERN_DIR   (as draws.sh)
set -euo pipefail
dir=${1:?PATTERN_DIR}
here=$(cd "$(dirname "$0")" && pwd)
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
g++ -O2 -o "$t/gnd" "$here/gnd.cpp" -I/usr/include/suitesparse -lcholmod -lmetis -lamd
for g in g26 g104 g416; do
  seeds="-1 1 2 3 4 5"; [ $g != g416 ] || seeds="-1 1 2"
  for s in $seeds; do
    e=$((s + 1)); [ "$s" != -1 ] || e=0
    LEAF=0 "$t/gnd" "$dir/$g.bin" 0 "$s" $e | tail -1
    for leaf in 100 200 400; do LEAF=$leaf "$t/gnd" "$dir/$g.bin" 99 "$s" $e | tail -1; done
    for leaf in 1000 3000; do LEAFND=1 LEAF=$leaf "$t/gnd" "$dir/$g.bin" 99 "$s" $e | tail -1 | sed 's/ mode ring1/ mode ring1-nd/'; done
  done
done | sed "s#$dir/##" > "$here/gnd.txt"
/usr/bin/python3 "$here/gnd_summary.py" "$here/gnd.txt" > "$here/gnd.md"
cat "$here/gnd.md"
