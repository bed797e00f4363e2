#!/usr/bin/env bash
# `deformbench deform --solver mumps` on 2 ranks of this machine (scripts/mpirun.sh: oversubscribed, as root too),
# end to end: the BS08 cylinder's LAP and TF edits; the mesh rank 0 writes must equal the exact one (the
# single-process multifrontal_refined at 1e-13; not a plain double solve, whose own error depends on the BLAS kernels
# and the thread count) to 1e-8 of the bounding-box diagonal, its CSV row names 2 ranks and each rank's peak RSS, and
# rank 0 alone prints the report (with its per-rank line); each rank holds only its share of the matrix. The same equality for what else the deform path does on
# ranks: soft constraints, TF's normalized scale pass, handle-mode frames (each rank assembling its own share of
# LAP's and TF's systems) and LRI (the whole system on every rank). mumps_refined on 2 ranks equals
# multifrontal_refined (the exact solution) to 1e-12. Another backend under 2 ranks is refused
# (exit 1), and so are the subcommands that do not run on ranks (coat, transplant, solvers).
#   mumps_deform_test.sh SOURCE_DIR BUILD_DIR
set -u
SRC=$1
EXE=$2/deformbench
. "$(dirname "$0")/check_lib.sh"  # $T, fail, ok, $fails
cd "$SRC" || exit 1
export OPENBLAS_NUM_THREADS=1
E=data/bs08/cylinder

# Largest vertex difference of two OFF meshes over the first one's bounding-box diagonal.
diff_off() {
  /usr/bin/python3 - "$1" "$2" <<'PY'
import sys
import numpy as np
def verts(p):
    t = open(p).read().split()
    nv = int(t[1])
    return np.array(t[4:4 + 3 * nv], dtype=float).reshape(nv, 3)
a, b = verts(sys.argv[1]), verts(sys.argv[2])
assert a.shape == b.shape, (a.shape, b.shape)
print(np.abs(a - b).max() / np.linalg.norm(a.max(0) - a.min(0)))
PY
}

EXACT=(--solver multifrontal_refined --refine-tolerance 1e-13)
for m in lap tf; do
  "$EXE" deform $E --method $m "${EXACT[@]}" --out "$T/mf_$m.off" >"$T/mf.out" 2>&1 ||
    { fail "$m multifrontal_refined: $(tail -c 300 "$T/mf.out")"; continue; }
  scripts/mpirun.sh 2 "$EXE" deform $E --method $m --solver mumps --frames 2 --out "$T/r2_$m.off" \
    --csv "$T/r2_$m.csv" >"$T/r2.out" 2>&1 || { fail "$m 2 ranks: $(tail -c 400 "$T/r2.out")"; continue; }
  d=$(diff_off "$T/mf_$m.off" "$T/r2_$m.off")
  /usr/bin/python3 -c "import sys; sys.exit(0 if float(sys.argv[1]) <= 1e-8 else 1)" "$d" &&
    ok "$m: 2 ranks = the exact mesh to $d of the diagonal (<= 1e-8)" || fail "$m: 2 ranks differ by $d"
  # Rank-local assembly: each rank hands the solver its share of the matrix, not the whole one.
  /usr/bin/python3 - "$T/mf.out" "$T/r2.out" <<'PY' && ok "$m: each rank holds a share of the matrix" || fail "$m: shares"
import re, sys
whole = float(re.search(r"^matrix ([0-9.]+) MB", open(sys.argv[1]).read(), re.M).group(1))
share = [float(x) for x in re.search(r"matrix per rank MB: ([0-9. ]+)", open(sys.argv[2]).read()).group(1).split()]
sys.exit(0 if len(share) == 2 and max(share) < 0.75 * whole and sum(share) > 0.9 * whole else 1)
PY
  [ "$(grep -c '^build .* | init ' "$T/r2.out")" = 1 ] && grep -q "^2 ranks .* peak RSS per rank MB: [0-9]* [0-9]*" "$T/r2.out" &&
    ok "$m: rank 0 alone prints, with each rank's peak RSS" || fail "$m: report: $(head -c 600 "$T/r2.out")"
  /usr/bin/python3 - "$T/r2_$m.csv" <<'PY' && ok "$m: the row names 2 ranks, both RSS, provenance" || fail "$m: CSV row"
import csv, sys
r = list(csv.DictReader(open(sys.argv[1])))
sys.exit(0 if len(r) == 1 and r[0]["ranks"] == "2" and len(r[0]["peak_rss_rank_bytes"].split()) == 2
         and r[0]["backend"] == "mumps" and r[0].get("git_sha") else 1)
PY
done
# The rest of the deform path on 2 ranks, against the same options in one process with the exact backend.
variants=("tf --constraints soft --soft-weight 3" "tf --tf-scale normalized" "lap --frame-mode handle"
          "tf --constraints soft --frame-mode handle" "lri")
for v in "${variants[@]}"; do
  read -r -a opts <<<"$v"
  "$EXE" deform $E --method "${opts[@]}" "${EXACT[@]}" --out "$T/mf.off" >"$T/mf.out" 2>&1 ||
    { fail "$v multifrontal_refined: $(tail -c 300 "$T/mf.out")"; continue; }
  scripts/mpirun.sh 2 "$EXE" deform $E --method "${opts[@]}" --solver mumps --frames 2 --out "$T/r2.off" \
    >"$T/r2.out" 2>&1 || { fail "$v 2 ranks: $(tail -c 400 "$T/r2.out")"; continue; }
  d=$(diff_off "$T/mf.off" "$T/r2.off")
  /usr/bin/python3 -c "import sys; sys.exit(0 if float(sys.argv[1]) <= 1e-8 else 1)" "$d" &&
    ok "$v: 2 ranks = the exact mesh to $d of the diagonal (<= 1e-8)" || fail "$v: 2 ranks differ by $d"
  rm -f "$T/r2.off"
done

# mumps_refined: on 2 ranks (rank-local shares, products summed over the ranks in double-double) it reaches the
# exact solution, as multifrontal_refined does in one process; --vs-double compares with plain mumps on the ranks.
# Compared where the 2-rank system is bitwise the one-process system: TF soft's shares sum exactly, and LAP's naive
# build is whole on every rank. (LAP's rank-local shares sum some right-hand side entries in another order; on
# these ill-conditioned systems that moves the exact solution itself by ~1e-10 of the diagonal.)
for m in "tf --constraints soft" "lap --build naive"; do
  read -r -a opts <<<"$m"
  "$EXE" deform $E --method "${opts[@]}" --solver multifrontal_refined --refine-tolerance 1e-13 --out "$T/ref.off" \
    >"$T/ref.out" 2>&1 || { fail "$m multifrontal_refined: $(tail -c 300 "$T/ref.out")"; continue; }
  scripts/mpirun.sh 2 "$EXE" deform $E --method "${opts[@]}" --solver mumps_refined --refine-tolerance 1e-13 \
    --vs-double --out "$T/r2.off" --csv "$T/r2.csv" >"$T/r2.out" 2>&1 ||
    { fail "$m mumps_refined 2 ranks: $(tail -c 400 "$T/r2.out")"; continue; }
  d=$(diff_off "$T/ref.off" "$T/r2.off")
  /usr/bin/python3 -c "import sys; sys.exit(0 if float(sys.argv[1]) <= 1e-12 else 1)" "$d" &&
    ok "$m: mumps_refined on 2 ranks = multifrontal_refined to $d of the diagonal (<= 1e-12)" ||
    fail "$m: mumps_refined on 2 ranks differs by $d"
  /usr/bin/python3 - "$T/r2.csv" <<'PY' && ok "$m: the row has the refinement and the plain solve's distance" || fail "$m: mumps_refined row: $(cat "$T/r2.csv")"
import csv, sys
r = list(csv.DictReader(open(sys.argv[1])))[0]
sys.exit(0 if r["backend"] == "mumps_refined" and r["ranks"] == "2" and int(r["refine_iterations"]) > 0
         and float(r["refine_correction"]) <= 1e-13 and 0 <= float(r["mixed_vs_double"]) < 1e-6 else 1)
PY
  rm -f "$T/r2.off"
done

for sub in "coat data/bs08/cylinder.off data/bs08/cylinder.off --out $T/no.ply" \
           "transplant data/bs08/cylinder.off data/bs08/cylinder.off --out $T/no.ply" "solvers"; do
  read -r -a args <<<"$sub"
  scripts/mpirun.sh 2 "$EXE" "${args[@]}" >"$T/s.out" 2>&1
  rc=$?
  [ $rc -eq 1 ] && grep -q "started on 2 ranks: only .deformbench deform --solver mumps. runs under mpirun" "$T/s.out" &&
    [ ! -e "$T/no.ply" ] && ok "${args[0]} under 2 ranks refused (exit 1)" ||
    fail "${args[0]} under 2 ranks: exit $rc: $(tail -c 300 "$T/s.out")"
done

scripts/mpirun.sh 2 "$EXE" deform $E --method tf --solver multifrontal --out "$T/no.off" >"$T/s.out" 2>&1
[ $? -eq 1 ] && grep -q "only --solver mumps or mumps_refined runs distributed" "$T/s.out" && [ ! -e "$T/no.off" ] &&
  ok "another backend under 2 ranks refused (exit 1)" || fail "multifrontal under 2 ranks: $(tail -c 300 "$T/s.out")"
scripts/mpirun.sh 2 "$EXE" deform $E.nope --solver mumps --out "$T/no.off" >"$T/b.out" 2>&1
rc=$?
[ $rc -ne 0 ] && [ ! -e "$T/no.off" ] && ok "bad input under 2 ranks fails on every rank (exit $rc)" ||
  fail "bad input under 2 ranks: exit $rc: $(tail -c 300 "$T/b.out")"

if ((fails)); then echo "$fails failure(s)"; exit 1; fi
echo "all passed"
