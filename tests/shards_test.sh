#!/usr/bin/env bash
# Sharded grids end to end: a small Table 2-1 grid and a small solver-study grid run whole and as 2 shards
# (--shard 1/2, --shard 2/2), the shards merged (--merge-shards 2); the merged CSVs must have the whole run's
# columns and the same rows in the same order (the key columns of dbtools.track.results, line by line), and
# the shards must not overlap. Bad shard specs and a merge with a missing shard are refused.
#   shards_test.sh SOURCE_DIR BUILD_DIR
set -u
SRC=$1
BIN=$2
. "$(dirname "$0")/check_lib.sh"  # $T, fail, ok, $fails
cd "$SRC" || exit 1
PY=/usr/bin/python3
[ -x "$PY" ] || PY=python3

run() { # NAME EXPECTED_EXIT -- COMMAND...
  local name=$1 code=$2; shift 3
  "$@" >"$T/out" 2>&1
  local got=$?
  [ "$got" -eq "$code" ] && ok "$name" || fail "$name: exit $got, expected $code: $(tail -c 400 "$T/out")"
}

# The key columns of FILE's rows, in file order (dbtools.track.results' keys for that file name).
export PYTHONPATH=$PWD/python  # after cd "$SRC"
keys() {
  "$PY" - "$1" <<'EOF'
import csv, os, sys
from dbtools.track import results as cr
with open(sys.argv[1], newline="") as f:
    r = csv.DictReader(f)
    print(",".join(r.fieldnames))
    for row in r:
        print(",".join(row[k] for k in cr.KEYS[os.path.basename(sys.argv[1])]))
EOF
}
same_rows() { # NAME WHOLE MERGED
  if ! [ -s "$3" ]; then fail "$1: $3 missing"; return; fi
  if diff <(keys "$2") <(keys "$3") >"$T/diff"; then ok "$1: same columns and rows in the same order"
  else fail "$1: rows differ: $(head -c 400 "$T/diff")"; fi
}

# ------------------------------------------------------------------------------------------ Table 2-1
TAB=(--tier cactus=bs08/cactus.off --tier bar=bs08/bar.off --tier cylinder=bs08/cylinder.off --systems lap
     --builds naive,structured --frames 2 --repeats 1 --series cyl=bs08/cylinder.off+loop0..1)
run "table_2_1 whole" 0 -- "$BIN/exp_table_2_1" "${TAB[@]}" --results "$T/whole"
for i in 1 2; do
  run "table_2_1 shard $i/2" 0 -- "$BIN/exp_table_2_1" "${TAB[@]}" --results "$T/sharded" --shard $i/2
done
"$BIN/exp_table_2_1" "${TAB[@]}" --dry-run >"$T/all.txt"
cat <("$BIN/exp_table_2_1" "${TAB[@]}" --shard 1/2 --dry-run) <("$BIN/exp_table_2_1" "${TAB[@]}" --shard 2/2 --dry-run) |
  sort >"$T/both.txt"
[ -s "$T/all.txt" ] && diff <(sort "$T/all.txt") "$T/both.txt" >/dev/null && ok "table_2_1 shards cover the grid once" ||
  fail "table_2_1 shards do not partition the grid"
run "table_2_1 merge" 0 -- "$BIN/exp_table_2_1" "${TAB[@]}" --results "$T/sharded" --merge-shards 2
for f in table_2_1.csv scaling.csv scaling_fits.csv table_2_1_thesis.csv; do
  same_rows "table_2_1 $f" "$T/whole/$f" "$T/sharded/$f"
done
run "table_2_1 results compared" 0 -- "$PY" -m dbtools.track.results "$T/whole" "$T/sharded"

# ------------------------------------------------------------------------------------------ solver study
SOL=(--tier cactus=bs08/cactus.off --tier bar=bs08/bar.off --systems lap,tf
     --backends cholmod_supernodal,multifrontal,mumps --orderings default --factor-reps 1 --solve-reps 1)
run "solvers whole" 0 -- "$BIN/exp_solvers" "${SOL[@]}" --results "$T/swhole"
for i in 1 2; do
  run "solvers shard $i/2" 0 -- "$BIN/exp_solvers" "${SOL[@]}" --results "$T/ssharded" --shard $i/2
done
run "solvers merge" 0 -- "$BIN/exp_solvers" "${SOL[@]}" --results "$T/ssharded" --merge-shards 2
same_rows "solvers solvers.csv" "$T/swhole/solvers.csv" "$T/ssharded/solvers.csv"
grep -q "error_vs_cholmod" "$T/ssharded/solvers.csv" && ok "solvers shards measure error_vs_cholmod" ||
  fail "no error_vs_cholmod in the merged solvers.csv"

# ------------------------------------------------------------------------------------------ refusals
for bad in 0/2 3/2 1/0 x/2 1/ 2; do
  run "--shard $bad refused" 1 -- "$BIN/exp_solvers" "${SOL[@]}" --shard "$bad" --dry-run
done
run "--shard with --merge-shards refused" 1 -- "$BIN/exp_solvers" "${SOL[@]}" --shard 1/2 --merge-shards 2
rm -r "$T/ssharded/shards/2-of-2"
run "merge with a missing shard refused" 2 -- "$BIN/exp_solvers" "${SOL[@]}" --results "$T/ssharded" --merge-shards 2
grep -q "did that shard run" "$T/out" && ok "the missing shard is named" || fail "message: $(head -c 300 "$T/out")"

if ((fails)); then echo "$fails failure(s)"; exit 1; fi
echo "all passed"
