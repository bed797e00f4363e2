#!/usr/bin/env bash
# `deformbench advise` on a small generated mesh with three backends: the ranked table (a row per backend, a
# status each), the verdict line, the CSV's columns (with provenance) and the Markdown; --predict-only runs
# nothing; a budget nothing fits leaves no verdict of a backend; `deform` refuses a run predicted over its budget
# (exit 4) before building. No timing is asserted.
# usage: advise_test.sh PATH/TO/deformbench PATH/TO/meshtool
BIN=$1
MESHTOOL=$2
source "$(dirname "${BASH_SOURCE[0]}")/check_lib.sh"  # $T, expect, ok, fail

"$MESHTOOL" generate plane "$T/plane.off" nx=16 ny=16 >/dev/null || { echo "FAIL meshtool generate"; exit 1; }
printf 'mesh = plane.off\nroi = all\nhandle = nearest:0.5,0.5,0,8\ntransform = translate:0,0,0.1\n' >"$T/plane.edit"
B=multifrontal,cholmod_supernodal,cg_jacobi

expect "advise ranks three backends" 0 "^verdict: use " -- "$BIN" advise "$T/plane.edit" --method tf \
  --constraints soft --backends $B --frames 2 --csv "$T/advise.csv"
grep -Eq "^rank +backend" "$T/stdout" && ok "table header" || fail "no table header (rank backend ...)"
for b in multifrontal/metis multifrontal/amd cholmod_supernodal/metis cholmod_supernodal/amd cg_jacobi; do
  grep -Eq "^[0-9]+ +$b +ok " "$T/stdout" && ok "table row $b ok" || fail "no ok row for $b in the table"
done
head -1 "$T/advise.csv" | tr ',' '\n' >"$T/columns"
for c in rank backend ordering status init_s frame_s handle_frame_s peak_rss_bytes factor_bytes error_vs_refined \
  predicted_peak_bytes predicted_init_s git_sha blas_core; do
  grep -qx "$c" "$T/columns" && ok "CSV column $c" || fail "CSV lacks column $c"
done
[ "$(($(wc -l <"$T/advise.csv") - 1))" -eq 5 ] && ok "CSV has 5 rows" || fail "CSV rows: $(wc -l <"$T/advise.csv")"
grep -q "^| 1 | " "$T/advise.md" && grep -q "^verdict: use " "$T/advise.md" && ok "Markdown table and verdict" ||
  fail "advise.md lacks the table or the verdict"
# The rows' errors against the refined solution are numbers, all of them far below the mesh's size.
/usr/bin/python3 - "$T/advise.csv" <<'PY' && ok "errors against the refined solution" || fail "error_vs_refined"
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
errs = [float(r["error_vs_refined"]) for r in rows]
sys.exit(0 if all(math.isfinite(e) and e < 1e-2 for e in errs) else 1)
PY

# --calibrate measures the machine: an edit or a run's option beside it would be ignored, so it is refused.
expect "advise --calibrate with an edit" 1 "--calibrate measures this machine and takes no EDIT" -- "$BIN" advise \
  "$T/plane.edit" --calibrate
expect "advise --calibrate with --frames" 1 "--frames does not go with --calibrate" -- "$BIN" advise --calibrate --frames 3
expect "advise --predict-only" 0 "predicted" -- "$BIN" advise "$T/plane.edit" --method tf --constraints soft --backends $B \
  --predict-only
grep -q "verdict" "$T/stdout" && fail "--predict-only printed a verdict" || ok "--predict-only runs nothing"
expect "advise under a budget nothing fits" 0 "no backend finished" -- "$BIN" advise "$T/plane.edit" \
  --method tf --constraints soft --backends $B --budget-mb 1
grep -q "predicted over budget" "$T/stdout" "$T/stderr" && ok "budget: each backend predicted over it" || fail "no \"predicted over budget\" status"
expect "deform predicted over its budget" 4 "predicted to peak at .* over --memory-budget-mb 5; not started" -- \
  "$BIN" deform "$T/plane.edit" --method tf --constraints soft --build dense --memory-budget-mb 5 --out "$T/out.off"
# --scale 4: the plane Loop-subdivided once, V + E vertices (its edges counted here from the faces).
VE=$(/usr/bin/python3 -c "
import sys
t = open(sys.argv[1]).read().split()
nv, nf = int(t[1]), int(t[2])
f = [tuple(map(int, t[4 + 3 * nv + 4 * i + 1:4 + 3 * nv + 4 * i + 4])) for i in range(nf)]
print(nv + len({tuple(sorted((a[i], a[(i + 1) % 3]))) for a in f for i in range(3)}))" "$T/plane.off")
expect "advise --predict-only --scale 4" 0 "predicted at 4x the vertices \\(the mesh Loop-subdivided 1 time\\(s\\): $VE vertices\\)" \
  -- "$BIN" advise "$T/plane.edit" --method tf --constraints soft --backends multifrontal --predict-only --scale 4
expect "advise --scale without --predict-only" 1 "--scale predicts only" -- "$BIN" advise "$T/plane.edit" --scale 4

echo "$fails failed"
((fails == 0))
