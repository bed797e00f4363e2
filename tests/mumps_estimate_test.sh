#!/usr/bin/env bash
# MUMPS's analysis-only estimates with centralized input on 2 ranks of this machine (scripts/mpirun.sh):
# `exp_mumps_ranks --analysis-only --input centralized` on the BS08 cylinder's TF system. Rank 0 alone builds the
# pattern (built_ranks=1), its entry count equals the full build's K, the estimates are present and positive on
# both ranks, and with a deterministic ordering (AMD) the estimated flops and factor entries equal those of the
# same analysis on the values that every rank built (--input split). Without --analysis-only it is refused (1).
#   mumps_estimate_test.sh SOURCE_DIR BUILD_DIR
set -u
SRC=$1
EXE=$2/exp_mumps_ranks
. "$(dirname "$0")/check_lib.sh"  # $T, fail, ok, $fails
cd "$SRC" || exit 1
export OPENBLAS_NUM_THREADS=1
M=data/bs08/cylinder.off
positive() { /usr/bin/python3 -c "import sys; sys.exit(0 if all(float(x) > 0 for x in sys.argv[1:]) else 1)" "$@"; }

scripts/mpirun.sh 2 "$EXE" --mesh $M --analysis-only --input centralized --ordering amd --csv "$T/c.csv" \
  >"$T/c.out" 2>&1 || fail "centralized: $(tail -c 300 "$T/c.out")"
scripts/mpirun.sh 2 "$EXE" --mesh $M --analysis-only --input split --ordering amd >"$T/s.out" 2>&1 ||
  fail "split: $(tail -c 300 "$T/s.out")"
[ "$(value ranks "$T/c.out")" = 2 ] && [ "$(value built_ranks "$T/c.out")" = 1 ] &&
  [ "$(value built_ranks "$T/s.out")" = 2 ] && ok "centralized: rank 0 alone built (split: both)" ||
  fail "built_ranks: centralized $(value built_ranks "$T/c.out"), split $(value built_ranks "$T/s.out")"
nnz=$(value nnz_upper "$T/c.out")
[ -n "$nnz" ] && [ "$nnz" = "$(value nnz_upper "$T/s.out")" ] && ok "the pattern has K's $nnz entries" ||
  fail "pattern entries $nnz, K's $(value nnz_upper "$T/s.out")"
est=()
for k in flops_estimated factor_entries_estimated mb_in_core_max mb_in_core_sum mb_ooc_max mb_ooc_sum; do
  est+=("$(value $k "$T/c.out")")
done
positive "${est[@]}" 2>/dev/null && ok "estimates positive: ${est[*]}" || fail "estimates: ${est[*]}"
per_rank=$(grep -o "mb_in_core_rank=[0-9.]* [0-9.]*" "$T/c.out" | cut -d= -f2)
# shellcheck disable=SC2086
[ -n "$per_rank" ] && positive $per_rank && ok "per-rank in-core estimates: $per_rank" ||
  fail "per-rank estimates: $(grep -o 'mb_in_core_rank=[^=]*' "$T/c.out")"
for k in flops_estimated factor_entries_estimated; do
  [ "$(value $k "$T/c.out")" = "$(value $k "$T/s.out")" ] && ok "$k equal to the split input's" ||
    fail "$k: centralized $(value $k "$T/c.out"), split $(value $k "$T/s.out")"
done
[ "$(head -1 "$T/c.csv" | tr ',' '\n' | grep -c -e '^git_sha$' -e '^peak_rss_rank_bytes$' -e '^built_ranks$')" = 3 ] &&
  ok "the row has provenance, per-rank RSS, built_ranks" || fail "the row lacks provenance: $(head -1 "$T/c.csv")"
scripts/mpirun.sh 2 "$EXE" --mesh $M --input centralized >"$T/r.out" 2>&1
[ $? -eq 1 ] && grep -q "analysis of the pattern" "$T/r.out" && ok "centralized without --analysis-only refused" ||
  fail "centralized without --analysis-only: $(tail -c 300 "$T/r.out")"

if ((fails)); then echo "$fails failure(s)"; exit 1; fi
echo "all passed"
