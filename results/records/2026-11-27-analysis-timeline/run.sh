#!/usr/bin/env bash
# The analysis phase step by step: a build with timeline.patch (applies to the commit in README.md) prints one
# line per step (the 2-ring pattern, each METIS split and side extraction by dissection level, each part's
# METIS_NodeND, the postordering analysis, the multifrontal symbolic analysis); ROUNDS runs of the 104k and the
# 416k TF deformations at 1 and 2 threads. Writes timeline.txt (every line, a "# edit threads round" line before
# each run) and table.md (scripts/analysis_timeline.py) here.
# usage: results/records/2026-11-27-analysis-timeline/run.sh DIAG_BINARY [ROUNDS]   (from the repository root;
#        data/generated/armadillo_loop2.off as in ../2026-11-27-init-floor)
set -euo pipefail
diag=$1 rounds=${2:-2}
here=$(cd "$(dirname "$0")" && pwd)
t=$(mktemp -d); trap 'rm -rf "$t"' EXIT
for ((r = 1; r <= rounds; r++)); do
  for edit in armadillo_loop1_whole armadillo_loop2_whole; do
    for threads in 1 2; do
      echo "# $edit, $threads threads, round $r"
      DEFORMBENCH_THREADS=$threads OPENBLAS_NUM_THREADS=$threads "$diag" deform "data/edits/$edit.edit" --method tf \
        --constraints soft --frames 1 --out "$t/o.ply" 2>&1 >/dev/null | grep '^TIMELINE' || true
    done
  done
done > "$here/timeline.txt"
/usr/bin/python3 scripts/analysis_timeline.py "$here/timeline.txt" > "$here/table.md"
grep '^analysis' "$here/table.md"
