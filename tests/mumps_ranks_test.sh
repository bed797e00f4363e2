#!/usr/bin/env bash
# The distributed MUMPS driver end to end on 2 ranks of this machine (scripts/mpirun.sh: oversubscribed, as root
# too): the TF and LAP systems of the BS08 cylinder solved by DistributedMumps on 2 ranks, each passing its own
# columns, must equal the exact solution (multifrontal_refined in one process; not a plain double solve, whose own
# error depends on the BLAS kernels and the thread count) to 1e-8 of the bounding-box diagonal; the
# analysis-only run reports MUMPS's per-rank estimates; a one-process backend under 2 ranks is refused (exit 1).
#   mumps_ranks_test.sh SOURCE_DIR BUILD_DIR
set -u
SRC=$1
EXE=$2/exp_mumps_ranks
. "$(dirname "$0")/check_lib.sh"  # $T, fail, ok, $fails
cd "$SRC" || exit 1
export OPENBLAS_NUM_THREADS=1
M=data/bs08/cylinder.off

for sys in tf lap; do
  "$EXE" --mesh $M --system $sys --solver multifrontal_refined --positions "$T/mf_$sys.bin" >"$T/mf.out" 2>&1 ||
    { fail "$sys multifrontal_refined: $(tail -c 300 "$T/mf.out")"; continue; }
  scripts/mpirun.sh 2 "$EXE" --mesh $M --system $sys --compare "$T/mf_$sys.bin" --csv "$T/r2_$sys.csv" >"$T/r2.out" 2>&1 ||
    { fail "$sys 2 ranks: $(tail -c 300 "$T/r2.out")"; continue; }
  d=$(value max_diff_vs_compare "$T/r2.out")
  [ "$(value ranks "$T/r2.out")" = 2 ] && ok "$sys: 2 ranks ran" || fail "$sys: not 2 ranks"
  /usr/bin/python3 -c "import sys; d=float(sys.argv[1]); sys.exit(0 if d <= 1e-8 else 1)" "$d" &&
    ok "$sys: 2 ranks = the exact solution to $d of the diagonal (<= 1e-8)" || fail "$sys: 2 ranks differ by $d"
  [ "$(head -1 "$T/r2_$sys.csv" | tr ',' '\n' | grep -c -e git_sha -e peak_rss_rank_bytes)" = 2 ] &&
    ok "$sys: the row has provenance and per-rank RSS" || fail "$sys: the row lacks provenance or per-rank RSS"
done
scripts/mpirun.sh 2 "$EXE" --mesh $M --analysis-only --input root >"$T/a.out" 2>&1 &&
  [ "$(value mb_in_core_rank "$T/a.out")" != "" ] && grep -q "mb_in_core_rank=[0-9.]* [0-9]" "$T/a.out" &&
  ok "analysis only: per-rank estimates" || fail "analysis only: $(tail -c 300 "$T/a.out")"
scripts/mpirun.sh 2 "$EXE" --mesh $M --solver multifrontal >"$T/s.out" 2>&1
[ $? -eq 1 ] && grep -q "runs in one process" "$T/s.out" && ok "a one-process backend under 2 ranks refused" ||
  fail "one-process backend under 2 ranks: $(tail -c 300 "$T/s.out")"

if ((fails)); then echo "$fails failure(s)"; exit 1; fi
echo "all passed"
