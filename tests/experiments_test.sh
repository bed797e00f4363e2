#!/usr/bin/env bash
# The experiment drivers end to end: strict command lines (generated --help, misspelled options and config keys,
# numbers out of range, unwritable outputs: exit 1, nothing written), the shipped configs (data/experiments/*.toml
# load and give the grids), a tiny run of every driver on a bundled mesh, and the report step (dbtools.report) on
# its CSVs: figures under RESULTS/figures/ and nowhere else, then the reports citing them.
#   experiments_test.sh SOURCE_DIR BUILD_DIR
set -u
SRC=$1
BIN=$2
. "$(dirname "$0")/check_lib.sh"  # $T, fail, ok, expect, $fails
cd "$SRC" || exit 1
PY=/usr/bin/python3
[ -x "$PY" ] || PY=python3
export PYTHONPATH="$SRC/python" PYTHONDONTWRITEBYTECODE=1  # the one Python package, run as $PY -m dbtools.<module>
report() { "$PY" -m dbtools.report "$@"; }  # the report step



# ---------------------------------------------------------------- strict command lines, configs
for d in table_2_1 solvers frames deform_cases; do
  exe="$BIN/exp_$d"
  expect "$d --help" 0 "Usage: exp_$d" -- "$exe" --help
  expect "$d misspelled option" 1 "unknown option --frme|did you mean" -- "$exe" --frme 3
  expect "$d config parses, grid listed" 0 "^kind=" -- "$exe" --dry-run
  printf 'bogus-key = 1\n' >"$T/bad.toml"
  expect "$d unknown config key" 1 "bogus" -- "$exe" --config "$T/bad.toml" --dry-run
  expect "$d missing config file" 1 "not readable|missing" -- "$exe" --config "$T/none.toml" --dry-run
done
# Configs are strict TOML (harness/toml_config.h), every error with file:line:column: a list left unclosed before
# the next key (CLI11's reader built the list from that line), a list open at the end of the file, a key given
# twice, a key that is no option, a table. Each exits 1, nothing run.
printf 'case = ["bs08_bar=bs08/bar", "bs08_plane=bs08/plane"\nframes = 3\n' >"$T/unclosed.toml"
printf 'frames = 3\ncase = ["bs08_bar=bs08/bar",\n' >"$T/open_end.toml"
printf 'frames = 3\nframes = 4\n' >"$T/twice.toml"
printf 'frames = 3\nframez = 3\n' >"$T/unknown.toml"
printf 'frames = 3\n[deform]\nmethods = ["lap"]\n' >"$T/table.toml"
DC="$BIN/exp_deform_cases"
expect "config: list unclosed before the next key" 1 "unclosed.toml:2:1: .*expected comma or closing" -- "$DC" --config "$T/unclosed.toml" --dry-run
expect "config: list open at the end" 1 "open_end.toml:2:[0-9]+: .*end-of-file" -- "$DC" --config "$T/open_end.toml" --dry-run
expect "config: key given twice" 1 "twice.toml:2:[0-9]+: .*redefine.*frames" -- "$DC" --config "$T/twice.toml" --dry-run
expect "config: key that is no option" 1 "unknown.toml:2:[0-9]+: 'framez' is no option of exp_deform_cases" -- "$DC" --config "$T/unknown.toml" --dry-run
expect "config: a table" 1 "table.toml:[0-9]+:[0-9]+: 'deform'" -- "$DC" --config "$T/table.toml" --dry-run
printf 'case = ["bs08_bar=bs08/bar"]\nmethods = ["tf"]\nframes = 3\n' >"$T/good.toml"
expect "config: a strict file is applied" 0 "^kind=deform model=bs08_bar .*method=tf .*frames=3" -- "$DC" --config "$T/good.toml" --dry-run
expect "table_2_1 frames out of range" 1 "frames" -- "$BIN/exp_table_2_1" --frames 0 --dry-run
expect "table_2_1 frames not whole" 1 "whole number" -- "$BIN/exp_table_2_1" --frames 2.5 --dry-run
expect "table_2_1 unknown tier" 1 "no such tier" -- "$BIN/exp_table_2_1" --only plank --dry-run
expect "table_2_1 own mesh" 0 "model=mine mesh=/some/mine.off" -- "$BIN/exp_table_2_1" --mesh mine=/some/mine.off --only mine --dry-run
expect "table_2_1 bad loop level" 1 "Loop level" -- "$BIN/exp_table_2_1" --mesh mine=x.off+loopx --dry-run
expect "solvers unknown backend" 1 "not one of" -- "$BIN/exp_solvers" --backends cholmod --dry-run
touch "$T/afile"
expect "solvers factor dir missing" 1 "does not exist" -- "$BIN/exp_solvers" --factor-dir "$T/nodir" --dry-run
expect "solvers results not a directory" 1 "not a directory" -- "$BIN/exp_solvers" --results "$T/afile/results" --dry-run
expect "frames malformed case" 1 "kind 'bnd'" -- "$BIN/exp_frames" --case "x: bnd mesh=a" --dry-run
expect "frames out into a missing directory" 1 "does not exist" -- "$BIN/exp_frames" --out "$T/no/frames.csv"
expect "deform_cases csv extension" 1 "extension" -- "$BIN/exp_deform_cases" --out "$T/cases.txt"
expect "applications --help" 0 "Usage: exp_applications" -- "$BIN/exp_applications" --help
expect "applications config parses, grid listed" 0 "^kind=application" -- "$BIN/exp_applications" --dry-run
expect "applications malformed case" 1 "not coat or transplant" -- "$BIN/exp_applications" --case "x: cot source=a target=b" --dry-run
expect "applications unknown case key" 1 "unknown key zon" -- "$BIN/exp_applications" --case "x: transplant source=bs08/plane.off target=bs08/plane.off zon=1" --dry-run
[ -z "$(ls "$T" | grep -v -e stdout -e stderr -e '^output$' -e '\.toml$' -e afile)" ] && ok "nothing written by the failures" ||
  fail "files left: $(ls "$T")"

# ---------------------------------------------------------------- tiny runs and the report step
R="$T/results"
mkdir -p "$R"
expect "table_2_1 tiny run" 0 "wrote" -- "$BIN/exp_table_2_1" --tier cactus=bs08/cactus.off --systems lap \
  --builds naive,structured --frames 2 --repeats 1 --series cactus_loop=bs08/cactus.off+loop0..0 --results "$R"
mkdir -p "$T/ooc"
expect "solvers tiny run" 0 "wrote" -- "$BIN/exp_solvers" --tier cactus=bs08/cactus.off --systems lap \
  --backends cholmod_supernodal,multifrontal,multifrontal_refined,multifrontal_mixed,spqr --orderings default \
  --factor-reps 1 --solve-reps 1 --factor-dir "$T/ooc" --results "$R"
expect "frames tiny run" 0 "wrote" -- "$BIN/exp_frames" --case "bar: twist mesh=bar:2:2:8:1:1:4 z0=0 z1=4 turns=1 chained=no" \
  --methods lap,tf,tf-normalized,lri,lri-uncoordinated --lri-frames first,random --lri-orthonormalize polar \
  --meshes "$R/meshes/frames" --out "$R/frames.csv"
expect "deform_cases tiny run" 0 "wrote" -- "$BIN/exp_deform_cases" --case bar=bs08/bar --methods lap --frames 2 \
  --out "$R/deform_cases.csv"
expect "applications tiny run" 0 "wrote" -- "$BIN/exp_applications" --meshes "$R/meshes/applications" \
  --case "flat: coat source=bs08/plane.off target=plane:20:20:1:0:1 target_region=sphere:0,0,0,0.4" --out "$R/applications.csv"
# The step after the drivers, as ./run reproduce runs it: every figure, then every report, which cite them. It
# writes under the results directory only: no figure anywhere else (a source folder such as the old plots/).
touch "$T/before_report"
expect "figures, then reports" 0 "frames.md: written" -- report --results "$R"
for png in render_app_flat render_bar table_2_1_memory table_2_1_init scaling solvers_orderings frames_quality; do
  [ -s "$R/figures/$png.png" ] && ok "figure $png.png" || fail "no figure $png.png"
done
strays=$(find "$SRC" "$T" -path "$SRC/build*" -prune -o -name '*.png' -newer "$T/before_report" -print | grep -v "^$R/figures/")
[ -z "$strays" ] && ok "every figure under RESULTS/figures" || fail "figures outside RESULTS/figures: $strays"
grep -Eq 'png` *\(?missing' "$R"/*.md && fail "a report cites a missing figure: $(grep -Eho '[a-z_0-9]*\.png` *\(?missing' "$R"/*.md)" \
  || ok "no report cites a missing figure"
[ ! -e "$R/figures/solvers_blas.png" ] && grep -q "no kernel comparison" "$R/solvers.md" \
  && ok "one BLAS kernel set: no comparison, and the report says so" || fail "a BLAS comparison of one kernel set"
# Kernel sets are told apart by the core OpenBLAS reported: a second run on this run's core is left out, a run on
# another core is compared, and two cores that load the same kernels (data/experiments/blas_kernel_sets.txt) count
# once. The copies below stand for such runs.
blas_step() { report --results "$R" --only solvers 2>/dev/null; }
as_core() {  # as_core CORE NAME: solvers.csv with another blas_core, as results/solvers_blas_NAME.csv
  "$PY" -c 'import csv, sys; r = list(csv.DictReader(open(sys.argv[1]))); w = csv.DictWriter(open(sys.argv[2], "w"), r[0].keys())
w.writeheader(); w.writerows(dict(x, blas_core=sys.argv[3]) for x in r)' "$R/solvers.csv" "$R/solvers_blas_$2.csv" "$1"; }
cp "$R/solvers.csv" "$R/solvers_blas_same.csv"
blas_step && [ ! -e "$R/figures/solvers_blas.png" ] && grep -q "solvers_blas_same.csv. reports core .*: left out" "$R/solvers.md" \
  && ok "a kernel set run twice is not compared with itself" || fail "a kernel set compared with itself"
as_core OtherCore other && as_core Cooperlake x1 && as_core SapphireRapids x2
blas_step && [ -s "$R/figures/solvers_blas.png" ] && grep -q "^### .* core OtherCore" "$R/solvers.md" \
  && grep -q "solvers_blas_x2.csv. reports core SapphireRapids, which loads the SkylakeX kernels of the" "$R/solvers.md" \
  && ok "distinct kernel sets compared, one set's two cores once" || fail "kernel sets: distinct not compared, or one twice"
rm -f "$R"/solvers_blas_*.csv "$R/figures/solvers_blas.png"
"$PY" -c 'import sys; from dbtools.plots import styles; p = styles.check(); print(*p, sep="\n"); sys.exit(bool(p))' \
  && ok "style table: distinct colours and markers" || fail "style table"
grep -q "^| cactus | lap | naive |" "$R/table_2_1.md" && ok "table_2_1.md has the cells" || fail "table_2_1.md lacks the cells"
grep -q "^| cactus | lap | .* | spqr |" "$R/solvers.md" && ok "solvers.md has the spqr row" || fail "solvers.md lacks spqr"
grep -q "^| bar | single |" "$R/frames.md" && ok "frames.md has the case" || fail "frames.md lacks the case"
grep -q "^| bar | TF normalized | " "$R/frames.md" && grep -q "## TF without the scale blow-up" "$R/frames.md" \
  && ok "frames.md compares tf-normalized" || fail "frames.md lacks the tf-normalized comparison"
grep -q "^## Thesis fig. 4-4" "$R/figures.md" && ok "figures.md written" || fail "figures.md lacks fig. 4-4"
grep -q "error_vs_cholmod" "$R/solvers.csv" && ok "error_vs_cholmod measured" || fail "no error_vs_cholmod"
grep -q "error_vs_refined" "$R/solvers.csv" && grep -q "^| cactus | lap | .* | ok |" <(sed -n '/^## Mixed precision/,/^## /p' "$R/solvers.md") \
  && ok "mixed row against double and refined, out of core" || fail "no mixed-precision row with error_vs_refined"
grep -q ",peak_rss_bytes," "$R/frames.csv" || head -1 "$R/frames.csv" | grep -q "peak_rss_bytes" && ok "frames rows carry peak RSS" || fail "frames lacks peak_rss_bytes"
expect "report unknown name" 1 "unknown experiment" -- report --results "$R" --only tables
expect "report on a missing directory" 1 "not a directory" -- report --results "$T/none"
# A figure module that fails costs only its figures: the other figures and every report are written, exit 1.
mkdir -p "$T/broken_figures/meshes/frames" && cp "$R"/frames*.csv "$T/broken_figures/"
printf 'ply\nformat binary_little_endian 1.0\nelement vertex 3\n' >"$T/broken_figures/meshes/frames/x__rest.ply"
expect "a failed figure module" 1 "figures failed: render_meshes" -- report --results "$T/broken_figures" --only frames
[ -s "$T/broken_figures/figures/frames_quality.png" ] && grep -q "^# Does the LRI" "$T/broken_figures/frames.md" &&
  grep -q "^# The thesis' figures" "$T/broken_figures/figures.md" && ok "the other figures and the reports still written" ||
  fail "a failed figure module stopped the step: $(ls "$T/broken_figures" "$T/broken_figures/figures" 2>&1 | tr '\n' ' ')"
# One Python package, imported as such: no module patches sys.path to find another.
patched=$(grep -rln "sys\.path" python experiments)
[ -z "$patched" ] && ok "no sys.path patching under python/ and experiments/" || fail "sys.path patched in: $patched"

# The handle-frames driver (experiments/handle_frames.py: minutes on the armadillo, so not run here) and its report,
# written by the report step from the CSVs of its kept record.
expect "handle_frames driver --help" 0 "usage: handle_frames" -- "$PY" experiments/handle_frames.py --help
mkdir -p "$T/hf" && cp results/records/2026-11-24-handle-frames/*.csv "$T/hf/"
expect "handle_frames report from the record" 0 "handle_drags.md: written" -- report --results "$T/hf" --only handle_frames
spread="[0-9.]* ([0-9.]* - [0-9.]*, n=3)[ *(!)]*"  # a median over the record's 3 rounds with its spread
grep -q "^| armadillo_104k (soft) | tf | $spread | $spread | [0-9.]*x " "$T/hf/handle_frames.md" &&
  grep -q "^| armadillo_26k | lap | 30 | [0-9.]* |" "$T/hf/handle_drags.md" && ok "handle_frames.md and handle_drags.md have the cases" ||
  fail "handle_frames reports: $(grep -c '^| armadillo' "$T/hf"/handle_*.md | tr '\n' ' ')"

# ---------------------------------------------------------------- timings carry their spread (min, max, repeats)
grep -q ",frame_s,[^,]*,s," "$R/table_2_1.csv" && grep -q ",frame_min_s,[^,]*,s," "$R/table_2_1.csv" &&
  grep -q ",frame_max_s,[^,]*,s," "$R/table_2_1.csv" && grep -q ",frame_reps,2,count," "$R/table_2_1.csv" &&
  grep -q ",init_reps,1,count," "$R/table_2_1.csv" && ! grep -q "predicted_min_s" "$R/table_2_1.csv" &&
  ok "table_2_1.csv: timings with their spread (frames of the drag, runs)" || fail "table_2_1.csv lacks the spread rows"
grep -q ",factorize_max_s," "$R/solvers.csv" && grep -q ",solve_reps,1,count," "$R/solvers.csv" &&
  grep -q ",factorize_min_s," "$R/solvers.csv" && ok "solvers.csv: factorize and solve with their spread" ||
  fail "solvers.csv lacks the spread rows"
head -1 "$R/deform_cases.csv" | grep -q "frame_s,frame_min_s,frame_max_s,frame_reps" &&
  head -1 "$R/frames.csv" | grep -q "frame_s,frame_min_s,frame_max_s,frame_reps" &&
  ok "wide CSVs: the spread columns beside the median" || fail "wide CSVs lack the spread columns"
"$PY" - "$R/frames.csv" <<'PYEOF' && ok "frames.csv: every frame solved 5 times (4 after the first), min <= median <= max" || fail "frames.csv spread values"
import csv, sys
rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["status"] == "ok"]
assert rows and all(r["frame_reps"] == "4" for r in rows), [r["frame_reps"] for r in rows]
assert all(float(r["frame_min_s"]) <= float(r["frame_s"]) <= float(r["frame_max_s"]) for r in rows)
PYEOF
expect "deform --csv with the frame spread" 0 "frames after the first ranged" -- "$BIN/deformbench" deform data/bs08/bar \
  --method lap --frames 4 --out "$T/cli.ply" --csv "$T/cli.csv"
"$PY" - "$T/cli.csv" <<'PYEOF' && ok "the CLI row: frame_min_s <= frame_s <= frame_max_s over 3 frames" || fail "CLI spread columns"
import csv, sys
r = next(csv.DictReader(open(sys.argv[1])))
assert r["frame_reps"] == "3" and r["response_reps"] == "", r  # full frames: no responses measured
assert float(r["frame_min_s"]) <= float(r["frame_s"]) <= float(r["frame_max_s"]), r
PYEOF
grep -q "^| cactus | lap | structured | .*(.* - .*, n=1).* n=2)" "$R/table_2_1.md" &&
  grep -q "^| bar | lap | .* (.* - .*, n=4)" "$R/frames.md" && ok "table_2_1.md and frames.md show the spread" ||
  fail "the reports do not show the spread"

# Planted repeats: one cell's frames 10x apart is flagged, with the footnote; the others are as measured.
mkdir -p "$T/planted"
"$PY" - "$R" "$T/planted" <<'PYEOF'
import csv, sys
src, dst = sys.argv[1], sys.argv[2]
for name, match, key in (("table_2_1.csv", lambda r: r["build"] == "structured", "measure"),
                         ("frames.csv", lambda r: r["config"] == "tf", None)):
    rows = list(csv.DictReader(open(f"{src}/{name}")))
    for r in rows:
        if match(r):
            if key is None:
                r["frame_max_s"] = str(10 * float(r["frame_min_s"]))
            elif r[key] == "frame_max_s":
                lo = next(x for x in rows if match(x) and x[key] == "frame_min_s")["value"]
                r["value"] = str(10 * float(lo))
    with open(f"{dst}/{name}", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
PYEOF
expect "report on planted repeats" 0 "table_2_1.md: written" -- report --results "$T/planted" --only table_2_1,frames
grep -q '^| cactus | lap | structured | .*n=2) \*\*(!)\*\*' "$T/planted/table_2_1.md" &&
  grep -q '^| cactus | .* / [0-9.]* \*\*(!)\*\* |' "$T/planted/table_2_1.md" &&
  grep -q "more than 2x apart .*median may be unreliable" "$T/planted/table_2_1.md" &&
  ok "table_2_1.md flags the planted frame (phase table and fps) with the footnote" ||
  fail "table_2_1.md does not flag the planted frame: $(grep '^| cactus | lap | structured' "$T/planted/table_2_1.md" | head -2)"
grep -q '^| bar | tf | .*n=4) \*\*(!)\*\* |' "$T/planted/frames.md" && grep -q "more than 2x apart" "$T/planted/frames.md" &&
  ok "frames.md flags the planted frame" || fail "frames.md does not flag the planted frame"

# Reports get a new file's mode (0666 less the umask), as the CSVs do, not a temporary file's 0600.
(umask 022 && report --results "$R" --only table_2_1 2>/dev/null)
[ "$(stat -c %a "$R/table_2_1.md")" = 644 ] && [ "$(stat -c %a "$R/table_2_1.csv")" = "$(stat -c %a "$R/frames.md")" ] &&
  ok "reports are 0644 under umask 022, like the CSVs" || fail "report modes: $(stat -c '%n %a' "$R"/*.md "$R/table_2_1.csv")"
(umask 027 && report --results "$R" --only table_2_1 2>/dev/null)
[ "$(stat -c %a "$R/table_2_1.md")" = 640 ] && ok "a report respects the umask" || fail "umask 027 gave $(stat -c %a "$R/table_2_1.md")"

# ---------------------------------------------------------------- a failed cell: every row written, exit 5
printf 'OFF\n3 1 0\nnot a number\n' >"$T/broken.off"
expect "deform_cases with a failing cell" 5 "FAILED kind=deform model=broken" -- "$BIN/exp_deform_cases" \
  --case bar=bs08/bar,broken="$T/broken" --methods lap --frames 2 --out "$T/cases_failed.csv"
[ "$(grep -c ',ok,' "$T/cases_failed.csv")" = 1 ] && grep -q ',error,' "$T/cases_failed.csv" &&
  ok "deform_cases wrote the good and the failed row" || fail "deform_cases rows: $(cut -c 1-80 "$T/cases_failed.csv")"
expect "table_2_1 with a failing cell" 5 "1 cell\(s\) failed.*|FAILED kind=deform model=broken" -- "$BIN/exp_table_2_1" \
  --mesh broken="$T/broken.off" --only broken --no-scaling --systems lap --builds structured --repeats 1 --frames 2 \
  --results "$T/failed_results"
grep -q ",error," "$T/failed_results/table_2_1.csv" && ok "table_2_1.csv has the failed cell's rows" ||
  fail "table_2_1.csv lacks the failed cell"
expect "solvers with a failing cell" 5 "FAILED kind=solve model=broken" -- "$BIN/exp_solvers" --mesh broken="$T/broken.off" \
  --only broken --systems lap --backends cholmod_supernodal --orderings default --results "$T/failed_results"
# The solver study on an edit (issue 30): lri's two systems at two thread counts, the report's summary first and its
# Threads section; no --results: refused before any work (the repository's results/ is written only when asked).
expect "solvers without --results refused" 1 "--results DIR is required" -- "$BIN/exp_solvers" --backends cholmod_supernodal
expect "solvers --edit of no edit" 2 "nostem" -- "$BIN/exp_solvers" --edit bs08/nostem --results "$T/edit"
expect "solvers --edit lri at 1,2 threads" 0 "wrote" -- "$BIN/exp_solvers" --edit data/bs08/bar --method lri \
  --constraints soft --backends cholmod_supernodal,multifrontal --orderings default --threads 1,2 --factor-reps 1 \
  --solve-reps 1 --rep-seconds 0 --results "$T/edit"
for want in "bar,.*,lri-frames,cholmod_supernodal,.*,1,omp=1 blas=1 own=1,nnz_factor," \
            "bar,.*,lri-positions,multifrontal,.*,2,omp=1 blas=2 own=2,parallel_efficiency,[0-9]" \
            "bar,.*,lri-positions,cholmod_supernodal,.*,2,omp=1 blas=2 own=2,blas_threads_used,2,"; do
  grep -Eq "^$want" "$T/edit/solvers.csv" && ok "solvers --edit: a row $want" || fail "solvers --edit: no row $want"
done
report --results "$T/edit" --only solvers >/dev/null 2>&1
fastest=$(grep -n "^## Fastest choice" "$T/edit/solvers.md" | cut -d: -f1)
verdict=$(grep -n "^## Verdict" "$T/edit/solvers.md" | cut -d: -f1)
[ -n "$fastest" ] && [ -n "$verdict" ] && [ "$fastest" -lt "$verdict" ] && ok "solvers.md: the fastest choice first" ||
  fail "solvers.md: the fastest choice is not first"
grep -Eq "^\| bar \| lri-frames \| [a-z_]+/default \| .* \| [0-9.]+ \| [0-9.]+ \| [0-9.e+-]+ \((vs refined|exact)\) \|" \
  "$T/edit/solvers.md" && ok "solvers.md: the fastest choice with memory and accuracy" ||
  fail "solvers.md: the fastest choice lacks memory or accuracy"
grep -Eq "^\| bar \| lri-positions \| multifrontal \| default \| 2 \| omp=1 blas=2 own=2 \| .* \| [0-9.]+ \| [0-9.]+ \| ok \|" \
  "$T/edit/solvers.md" && ok "solvers.md: the Threads section" || fail "solvers.md: no Threads row"
expect "applications with a failing cell" 5 "FAILED kind=application name=broken" -- "$BIN/exp_applications" \
  --case "flat: coat source=bs08/plane.off target=plane:20:20:1:0:1 target_region=sphere:0,0,0,0.4" \
  --case "broken: coat source=$T/broken.off target=plane:20:20:1:0:1" --out "$T/apps_failed.csv"
[ "$(grep -c ',ok,' "$T/apps_failed.csv")" = 1 ] && grep -q ',error,' "$T/apps_failed.csv" &&
  ok "applications wrote the good and the failed row" || fail "applications rows: $(cut -c 1-80 "$T/apps_failed.csv")"

expect "frames with failing cells (killed at their timeout)" 5 "2 cell\(s\) failed" -- "$BIN/exp_frames" \
  --case "bar: twist mesh=bar:6:6:60:1:1:10 z0=0 z1=10 turns=1 chained=no" --methods lap,tf --frame-repeats 100000 \
  --cell-timeout-s 1 --no-meshes --out "$T/failed_results/frames.csv"
[ "$(grep -c ',error (timed out' "$T/failed_results/frames.csv")" = 2 ] && ok "frames.csv has the failed cells' rows" ||
  fail "frames.csv rows: $(cut -c 1-80 "$T/failed_results/frames.csv")"

# scripts/experiments.sh runs every driver even after one failed, then exits with the first failure's code and
# names the failed drivers (stub drivers in a copy of the tree: nothing measured, nothing of this tree touched).
mkdir -p "$T/tree/scripts" "$T/tree/data/experiments" "$T/stubs"
cp scripts/experiments.sh "$T/tree/scripts/"
cp data/experiments/blas_kernel_sets.txt "$T/tree/data/experiments/"
printf '#!/bin/sh
echo "blas_core: Haswell"
' >"$T/stubs/deformbench"  # one kernel set: no BLAS study runs
chmod +x "$T/stubs/deformbench"
for d in deform_cases table_2_1 solvers frames applications; do
  code=0; [ $d = table_2_1 ] && code=5; [ $d = frames ] && code=2
  printf '#!/bin/sh\necho %s >>"%s/ran"\nexit %s\n' "$d" "$T" "$code" >"$T/stubs/exp_$d"
  chmod +x "$T/stubs/exp_$d"
done
expect "experiments.sh goes on after a failed driver" 5 "failed: exp_table_2_1 \(exit 5\) exp_frames \(exit 2\)" -- \
  env EXPERIMENTS_FAILED="$T/failed_drivers" bash "$T/tree/scripts/experiments.sh" "$T/stubs"
grep -q applications "$T/ran" && [ "$(cat "$T/failed_drivers")" = "$(printf 'exp_table_2_1 (exit 5)\nexp_frames (exit 2)')" ] &&
  ok "every driver ran; the failed ones listed" || fail "drivers ran: $(tr '\n' ' ' <"$T/ran"); failed: $(cat "$T/failed_drivers")"

# ---------------------------------------------------------------- exp_tree_parallelism (counts of the plan)
expect "tree_parallelism threads out of range" 1 "65 is outside" -- "$BIN/exp_tree_parallelism" --edit data/bs08/bar \
  --threads 1,65 --csv "$T/tree.csv"
expect "tree_parallelism tiny run" 0 "wrote" -- "$BIN/exp_tree_parallelism" --edit data/bs08/bar --threads 1,2,4,8 \
  --csv "$T/tree.csv"
# The plan partitions the supernodes: T groups and the top phase hold every flop, and one thread has no top phase.
"$PY" - "$T/tree.csv" <<'PY' && ok "tree_parallelism: groups and top phase add up to the flops" ||
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert len(rows) == 8, len(rows)
for r in rows:
    T, flops = int(r["threads"]), float(r["flops"])
    assert abs(T * float(r["group_flops_mean"]) + float(r["top_flops"]) - flops) <= 1e-9 * flops, r
    assert float(r["group_flops_max"]) >= float(r["group_flops_mean"]) > 0, r
    assert T > 1 or (float(r["top_flops"]) == 0 and r["top_supernodes"] == "0"), r
    # The solves' plan (in factor entries): its largest group and top hold at most every entry, at least a T-th.
    path = float(r["solve_group_entries_max"]) + float(r["solve_top_entries"])
    assert int(r["nnz_L"]) / T <= path * (1 + 1e-12) and path <= int(r["nnz_L"]), r
    assert abs(float(r["solve_bound"]) - int(r["nnz_L"]) / path) <= 1e-9 * T, r
PY
  fail "tree_parallelism: the phases do not add up ($T/tree.csv)"

# ---------------------------------------------------------------- exp_analysis (the analysis phase per ordering)
expect "analysis unknown system" 1 "'xyz' is not one of" -- "$BIN/exp_analysis" --edit data/bs08/bar --system xyz --csv "$T/an.csv"
expect "analysis tiny run" 0 "wrote" -- "$BIN/exp_analysis" --edit data/bs08/bar --system lap,tf --orderings amd,metis \
  --rounds 2 --csv "$T/an.csv"
"$PY" - "$T/an.csv" <<'PY' && ok "analysis: a row per round, system and ordering; its phases add up" ||
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert len(rows) == 8, len(rows)
for r in rows:
    assert abs(float(r["order_s"]) + float(r["mf_analyze_s"]) - float(r["analysis_s"])) <= 1e-6, r
    assert int(r["nnz_L"]) > 0, r
same = {}
for r in rows:  # the orderings are deterministic: every round gives the same fill
    assert same.setdefault((r["system"], r["ordering"]), r["nnz_L"]) == r["nnz_L"], r
PY
  fail "analysis: the rows ($T/an.csv)"

# ---------------------------------------------------------------- exp_machine_rates
expect "machine_rates bad size" 1 "--gemm-size" -- "$BIN/exp_machine_rates" --gemm-size 10
expect "machine_rates bad first-touch size" 1 "--first-touch-mb" -- "$BIN/exp_machine_rates" --first-touch-mb 0
expect "machine_rates row" 0 "GFlop/s" -- "$BIN/exp_machine_rates" --gemm-size 256 --first-touch-mb 16 --csv "$T/rates.csv"
"$PY" - "$T/rates.csv" <<'PY' && ok "machine_rates: one row of positive rates with provenance" ||
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert len(rows) == 1 and float(rows[0]["blas_dgemm_flops"]) > 0 and float(rows[0]["memory_read_bytes_per_s"]) > 0, rows
assert float(rows[0]["first_touch_bytes_per_s"]) > 0 and rows[0]["first_touch_mb"] == "16", rows
assert rows[0]["git_sha"] and rows[0]["blas"], rows
PY
  fail "machine_rates: the row ($T/rates.csv)"

if ((fails)); then echo "$fails failure(s)"; exit 1; fi
echo "all passed"
