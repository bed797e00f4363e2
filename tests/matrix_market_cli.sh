#!/usr/bin/env bash
# Matrix Market out and in end to end on a BS08 edit: `deformbench export-system` writes the system, `exp_solvers
# --matrix` runs the study on it and gives the same factor statistics (nnz(L), flops) and the same residual as
# `exp_solvers --edit` on the edit it came from; a second export is the same bytes; bad input and bad options
# are refused with their documented exit codes (docs/cli.md) and nothing written.
#   matrix_market_cli.sh DEFORMBENCH EXP_SOLVERS SOURCE_DIR
set -u
DB=$1
EXP=$2
SRC=$3
. "$(dirname "$0")/check_lib.sh"  # $T, fail, ok, expect, $fails
cd "$SRC" || exit 1
E=data/bs08/cactus
PY=/usr/bin/python3
[ -x "$PY" ] || PY=python3

# ---------------------------------------------------------------- export
for m in "lap --constraints hard" "tf --constraints soft --soft-weight 2"; do
  name=${m%% *}
  expect "export $name" 0 "wrote" -- "$DB" export-system $E --method $m --out "$T/$name.mtx" --rhs "$T/${name}_b.mtx"
  "$DB" export-system $E --method $m --out "$T/${name}2.mtx" >/dev/null 2>&1
  cmp -s <(grep -v '^%' "$T/$name.mtx") <(grep -v '^%' "$T/${name}2.mtx") && ok "export $name: the same bytes twice" ||
    fail "export $name: two exports differ"
done
head -1 "$T/tf.mtx" | grep -q '^%%MatrixMarket matrix coordinate real symmetric$' && ok "tf.mtx: symmetric coordinate header" ||
  fail "tf.mtx header: $(head -1 "$T/tf.mtx")"
grep -q '^% .*blocks of 3.*method tf constraints=soft soft_weight=2' "$T/tf.mtx" && ok "tf.mtx says where it came from" ||
  fail "tf.mtx lacks its provenance comment"
expect "export lri frames" 0 "lri-frames" -- "$DB" export-system $E --method lri --out "$T/lri.mtx"
expect "export lri positions" 0 "lri-positions" -- "$DB" export-system $E --method lri --system positions --out "$T/lrip.mtx"
expect "export least squares" 0 "A [0-9]+ x [0-9]+" -- "$DB" export-system $E --method tf --constraints soft --least-squares \
  --out "$T/A.mtx" --rhs "$T/b.mtx"
head -1 "$T/A.mtx" | grep -q 'coordinate real general' && ok "least-squares A: general" || fail "least-squares A header"

# bad options: exit 1 before any file is written
expect "export lri --rhs" 1 "--rhs: lap and tf only" -- "$DB" export-system $E --method lri --out "$T/x.mtx" --rhs "$T/y.mtx"
expect "export lri --least-squares" 1 "lap and tf only" -- "$DB" export-system $E --method lri --least-squares --out "$T/x.mtx"
expect "export --system for lap" 1 "has one" -- "$DB" export-system $E --method lap --system frames --out "$T/x.mtx"
expect "export wrong extension" 1 "unsupported extension" -- "$DB" export-system $E --out "$T/x.txt"
expect "export bad edit" 2 "nostem" -- "$DB" export-system data/bs08/nostem --out "$T/x.mtx"
[ ! -e "$T/x.mtx" ] && [ ! -e "$T/y.mtx" ] && ok "nothing written on refusal" || fail "a refused export left a file"

# ---------------------------------------------------------------- the study on the exported system
common=(--backends cholmod_supernodal,multifrontal --orderings default,metis --factor-reps 1 --solve-reps 1 --rep-seconds 0)
expect "study --edit" 0 "wrote" -- "$EXP" --edit $E --method tf --constraints soft --soft-weight 2 "${common[@]}" --results "$T/re"
expect "study --matrix" 0 "wrote" -- "$EXP" --matrix "$T/tf.mtx,$T/tf_b.mtx" --matrix-block 3 "${common[@]}" --results "$T/rm"
"$PY" - "$T/re/solvers.csv" "$T/rm/solvers.csv" <<'PYEOF' && ok "--matrix: the same nnz(L), flops, n and residual as --edit" || fail "--matrix and --edit differ"
import csv, sys
def stats(path):
    out = {}
    for r in csv.DictReader(open(path)):
        if r["measure"] in ("n", "nnz", "nnz_factor", "factor_flops", "residual") and r["status"] == "ok":
            out[(r["backend"], r["ordering"], r["measure"])] = r["value"]
    return out
e, m = stats(sys.argv[1]), stats(sys.argv[2])
cells = {k[:2] for k in e}
ok = len(cells) == 4 and e == m and all(e[c + ("nnz_factor",)] and e[c + ("factor_flops",)] for c in cells)
if not ok:
    for k in sorted(set(e) | set(m)):
        if e.get(k) != m.get(k): print(k, e.get(k), m.get(k), file=sys.stderr)
sys.exit(0 if ok else 1)
PYEOF
expect "study --matrix without B" 0 "wrote" -- "$EXP" --matrix "$T/lap.mtx" --backends cholmod_supernodal --orderings default \
  --factor-reps 1 --solve-reps 1 --rep-seconds 0 --results "$T/rl"
grep -q '^lap,,matrix,cholmod_supernodal,.*,nnz_factor,[1-9]' "$T/rl/solvers.csv" && ok "--matrix without B: a row per measure" ||
  fail "--matrix without B: no nnz_factor row"

# ---------------------------------------------------------------- bad systems: exit 2 before any cell
printf '%%%%MatrixMarket matrix coordinate real general\n2 2 3\n1 1 1\n2 1 1\n2 2 1\n' >"$T/nonsym.mtx"
printf '%%%%MatrixMarket matrix coordinate real symmetric\n2 2 2\n1 1 1\n2 2 -3\n' >"$T/negdiag.mtx"
printf '%%%%MatrixMarket matrix coordinate real symmetric\n3 3 5\n1 1 1\n2 2 1\n' >"$T/short.mtx"
expect "study nonsymmetric matrix" 2 "not symmetric" -- "$EXP" --matrix "$T/nonsym.mtx" --results "$T/bad"
expect "study negative diagonal" 2 "diagonal entry 2 is -3" -- "$EXP" --matrix "$T/negdiag.mtx" --results "$T/bad"
expect "study truncated matrix" 2 "2 entries, but the header promises 5" -- "$EXP" --matrix "$T/short.mtx" --results "$T/bad"
expect "study B of the wrong size" 2 "rows, but the matrix has" -- "$EXP" --matrix "$T/lap.mtx,$T/tf_b.mtx" --results "$T/bad"
expect "study --matrix with --edit" 1 "excludes" -- "$EXP" --matrix "$T/lap.mtx" --edit $E --results "$T/bad"
expect "study method option without --edit" 1 "go with --edit" -- "$EXP" --method tf --results "$T/bad" --dry-run
expect "study --matrix-block not dividing n" 1 "not whole blocks" -- "$EXP" --matrix "$T/lap.mtx" --matrix-block 7 --results "$T/bad"
[ ! -e "$T/bad/solvers.csv" ] && ok "no CSV from a refused study" || fail "a refused study wrote a CSV"

exit $fails
