#!/usr/bin/env bash
# The analysis step by step in two diagnostic builds, alternating (base first in odd rounds): BASE_DIAG, the build
# before the guide with ../2026-11-27-analysis-timeline/timeline.patch; NEW_DIAG, the guided build with
# timeline.patch beside this script (it also times the 1-ring guide's pattern). ROUNDS runs of the 104k and the
# 416k TF deformations (--constraints soft --frames 1) at each of THREADS (default "2 4": one level of splits,
# where the two builds order alike, and two, where the new one is guided). Writes timeline.txt (every TIMELINE
# line, a "# binary edit threads round" line before each run), timeline.md (every run's steps,
# scripts/analysis_timeline.py) and splits.md (per binary, edit and threads: medians of the analysis, the
# patterns, the first split, the ordering and the postordering analysis) here, or in OUT when it is set.
# usage: [OUT=DIR] [THREADS="2 4"] results/records/2026-11-27-guided-splits/timeline.sh BASE_DIAG NEW_DIAG [ROUNDS]
#        (from the repository root; data/generated/armadillo_loop2.off as in ../2026-11-27-init-floor)
set -euo pipefail
base=$1 new=$2 rounds=${3:-3} threads_list=${THREADS:-2 4}
here=$(cd "$(dirname "$0")" && pwd)
out=${OUT:-$here}
mkdir -p "$out"
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
one() {  # label binary edit threads round
  echo "# $1 $3 $4 $5"
  DEFORMBENCH_THREADS=$4 OPENBLAS_NUM_THREADS=$4 "$2" deform "data/edits/$3.edit" --method tf \
    --constraints soft --frames 1 --out "$t/o.ply" 2>&1 >/dev/null | grep '^TIMELINE' || true
}
for ((r = 1; r <= rounds; r++)); do
  for edit in armadillo_loop1_whole armadillo_loop2_whole; do
    for threads in $threads_list; do
      if ((r % 2)); then one base "$base" $edit $threads $r; one new "$new" $edit $threads $r
      else one new "$new" $edit $threads $r; one base "$base" $edit $threads $r; fi
    done
  done
done > "$out/timeline.txt"
/usr/bin/python3 scripts/analysis_timeline.py "$out/timeline.txt" > "$out/timeline.md"
/usr/bin/python3 - "$out/timeline.txt" > "$out/splits.md" <<'PY'
import collections, statistics, sys
sys.path.insert(0, "scripts")
from analysis_timeline import runs
cells = collections.defaultdict(lambda: collections.defaultdict(list))
for label, steps in runs(sys.argv[1]):
    binary, edit, threads, _ = label.split()
    wall = collections.defaultdict(float)
    for what, level, n, start, end, tid in steps:
        wall[what] += end - start
    first = max((s for s in steps if s[0] == "split"), key=lambda s: s[1])
    c = cells[(edit, int(threads), binary)]
    c["analysis"].append(sum(wall[w] for w in ("ordering_pattern", "ordering_guide", "ordering", "postorder_analysis",
                                               "symbolic")))
    c["patterns"].append(wall["ordering_pattern"] + wall["ordering_guide"])
    c["first split"].append(first[4] - first[3])
    c["ordering"].append(wall["ordering"])
    c["postorder analysis"].append(wall["postorder_analysis"])
def med(xs): return "%.3f (%.3f-%.3f)" % (statistics.median(xs), min(xs), max(xs))
cols = ["analysis", "patterns", "first split", "ordering", "postorder analysis"]
print("| edit | threads | binary | runs | " + " s | ".join(cols) + " s |")
print("|---|---|---|---|" + "---|" * len(cols))
for key in sorted(cells):
    c = cells[key]
    print(f"| {key[0]} | {key[1]} | {key[2]} | {len(c['analysis'])} | " + " | ".join(med(c[k]) for k in cols) + " |")
PY
cat "$out/splits.md"
