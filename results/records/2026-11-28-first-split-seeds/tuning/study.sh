#!/usr/bin/env bash
# The first-split seeds study: first_split.cpp (built here into a temporary directory) on eight meshes, the
# bundled ones Loop-subdivided by meshtool into temporary copies (armadillo 0, 1, 2 levels; diplodocus 1; bunny00
# 1; ChineseDragon-10kv 2; camel 2; refined_elephant 1), at 1 and 4 dissection levels, 16 first-split seeds each,
# on two processes at once. Writes study.txt (every line) and study.md (summary.py) in the record's folder.
# usage: results/records/2026-11-28-first-split-seeds/tuning/study.sh [MESHTOOL]   (default build/meshtool)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../../.." && pwd)
meshtool=${1:-$root/build/meshtool}
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
g++ -O2 -o "$t/first_split" "$here/first_split.cpp" -I/usr/include/suitesparse -lcholmod -lmetis
mesh() {  # NAME LEVELS: the subdivided copy's path
  if [ "$2" = 0 ]; then echo "$root/data/meshes/$1.off"; return; fi
  "$meshtool" subdivide "$root/data/meshes/$1.off" "$t/$1_l$2.off" "$2" >/dev/null
  echo "$t/$1_l$2.off"
}
run() { for m in "$@"; do f=$(mesh "${m%:*}" "${m#*:}"); for L in 1 4; do "$t/first_split" "$f" $L 16; done; done; }
run armadillo:0 armadillo:1 diplodocus:1 bunny00:1 > "$t/a.txt" &
a=$!
run armadillo:2 ChineseDragon-10kv:2 camel:2 refined_elephant:1 > "$t/b.txt"
wait $a
cat "$t/a.txt" "$t/b.txt" | sed -e "s#$t/##" -e "s#$root/data/meshes/##" > "$here/../study.txt"
/usr/bin/python3 "$here/summary.py" "$here/../study.txt" > "$here/../study.md"
cat "$here/../study.md"
