#!/usr/bin/env bash
# The deeper splits' balance: draws.cpp (built here into a temporary directory) in the guided mode (ring1) at four
# levels, the splits below the first at ufactor 200 (METIS's own, kept), 100 and 50; the 104k pattern (METIS's
# default seed -1 and seeds 1-10) and the 416k pattern (-1 and 1-5), one process at a time. Writes balance.txt
# (every line) and balance.md (balance_summary.py) here.
# usage: results/records/2026-11-27-guided-splits-16-cores/tuning/balance.sh PATTERN_DIR   (as draws.sh)
set -euo pipefail
dir=${1:?PATTERN_DIR}
here=$(cd "$(dirname "$0")" && pwd)
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
g++ -O2 -o "$t/draws" "$here/draws.cpp" -I/usr/include/suitesparse -lcholmod -lmetis
for g in g104 g416; do
  end=11; [ $g = g104 ] || end=6
  for uf in 200 100 50; do MODE=1 UF2=$uf "$t/draws" "$dir/$g.bin" 4 -1 0; MODE=1 UF2=$uf "$t/draws" "$dir/$g.bin" 4 1 $end; done
done | sed "s#$dir/##" > "$here/balance.txt"
/usr/bin/python3 "$here/balance_summary.py" "$here/balance.txt" > "$here/balance.md"
cat "$here/balance.md"
