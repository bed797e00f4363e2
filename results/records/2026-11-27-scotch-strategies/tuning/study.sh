#!/usr/bin/env bash
# SCOTCH's nested dissection of whole 2-ring patterns under the strategies of strategies.sh against METIS_NodeND,
# over random draws (seeds 1-5; 1-3 at 416k), one thread, one process at a time. Writes study.csv (every run),
# study.md (summary.py) and strategies.txt here.
# usage: results/records/2026-11-27-scotch-strategies/tuning/study.sh PATTERN_DIR   (PATTERN_DIR holds g26.bin,
#        g104.bin and g416.bin, written by ../../2026-11-26-analysis-levers/tuning/dump_pattern.cpp from
#        data/edits/armadillo_whole.edit, armadillo_loop1_whole.edit and armadillo_loop2_whole.edit).
#        Needs libscotch-dev (Debian), CHOLMOD and METIS.
set -euo pipefail
dir=${1:?PATTERN_DIR}
here=$(cd "$(dirname "$0")" && pwd)
source "$here/strategies.sh"
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
g++ -O2 -o "$t/scotch_fill" "$here/scotch_fill.cpp" -I/usr/include/suitesparse -I/usr/include/scotch \
  -lcholmod -lmetis -lscotch -lscotcherr -lpthread -lm
names="default quality nd-fm0.2 nd-fm0.5 nd-band0.5 nd-best2-fm0.5"
echo "pattern,orderer,strategy,seed,n,time_s,nnz_l,flops" > "$t/study.csv"
for g in g26 g104 g416; do
  seeds="1 2 3 4 5"; [ "$g" = g416 ] && seeds="1 2 3"
  for s in $seeds; do
    "$t/scotch_fill" "$dir/$g.bin" metis "$s" | awk -v g=$g '{print g",metis,NodeND,"$3","$5","$7","$9","$11}' >> "$t/study.csv"
    for k in $names; do
      "$t/scotch_fill" "$dir/$g.bin" scotch "$s" "${strat[$k]}" |
        awk -v g=$g -v k=$k '{print g",scotch,"k","$3","$5","$7","$9","$11}' >> "$t/study.csv"
    done
  done
done
cp "$t/study.csv" "$here/study.csv"
for k in $names; do echo "$k: ${strat[$k]:-(the default strategy)}"; done > "$here/strategies.txt"
/usr/bin/python3 "$here/summary.py" "$here/study.csv" > "$here/study.md"
cat "$here/study.md"
