#!/usr/bin/env bash
# Bad input through `deformbench deform` (and export-system, which builds the same systems): each case gets its
# documented exit code (docs/cli.md "Exit codes": 1 usage, 2 bad input, 3 solver failure, 4 over budget), a message
# naming the cause, returns within seconds, and leaves no file behind (the output directory stays empty; inputs are
# unchanged).
# usage: cli_bad_input.sh PATH/TO/deformbench [SOURCE_DIR]
BIN=$1
SRC=${2:-$(cd "$(dirname "$0")/.." && pwd)}
source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"  # $T, the counters, the octahedron, write_off
L=$(mktemp -d)   # the tool's stdout and stderr
trap 'rm -rf "$T" "$L"' EXIT
O=$T/outdir # every case writes here; it must stay empty
mkdir -p "$O"

# expect NAME EXIT_CODE MESSAGE_REGEX -- deformbench args... (stricter than cli_lib's: the whole output directory
# stays empty and the inputs unchanged)
expect() {
  local name=$1 code=$2 re=$3; shift 4
  local before; before=$(cd "$T" && find . -path ./outdir -prune -o -type f -print0 | sort -z | xargs -0 md5sum)
  timeout 20 "$BIN" "$@" >"$L/stdout" 2>"$L/stderr"
  local got=$?
  local ok=1
  [ "$got" -eq "$code" ] || { echo "FAIL $name: exit $got, expected $code"; ok=0; }
  grep -Eqi -- "$re" "$L/stderr" || { echo "FAIL $name: message does not match /$re/:"; cat "$L/stderr"; ok=0; }
  if [ -n "$(ls -A "$O")" ]; then echo "FAIL $name: left behind: $(ls -A "$O")"; rm -rf "${O:?}"/*; ok=0; fi
  local after; after=$(cd "$T" && find . -path ./outdir -prune -o -type f -print0 | sort -z | xargs -0 md5sum)
  [ "$before" = "$after" ] || { echo "FAIL $name: the input files changed"; ok=0; }
  if ((ok)); then passes=$((passes + 1)); echo "ok   $name ($got): $(head -c 200 "$L/stderr")"; else fails=$((fails + 1)); fi
}

# expect_ok NAME FILES -- deformbench args... : exits 0 and writes exactly FILES (names in $O; then removed).
expect_ok() {
  local name=$1 files=$2; shift 3
  timeout 20 "$BIN" "$@" >"$L/stdout" 2>"$L/stderr"
  local got=$? wrote
  wrote=$(cd "$O" && find . -type f -size +0 | sed 's|^\./||' | sort | tr '\n' ' ')
  if [ "$got" -eq 0 ] && [ "$wrote" = "$files " ]; then passes=$((passes + 1)); echo "ok   $name (0)"
  else fails=$((fails + 1)); echo "FAIL $name: exit $got, wrote '$wrote', expected '$files '"; cat "$L/stderr"; fi
  rm -rf "${O:?}"/*
}

edit_for() { # stem: write STEM.sel (handle=4, fixed=5, rest free) and a .def moving the handle
  local n=$2
  { for ((i = 0; i < n; i++)); do
      if [ $i -eq 4 ]; then echo 2; elif [ $i -eq 5 ]; then echo 0; else echo 1; fi
    done; } >"$1.sel"
  printf '1 0 0 0.1\n0 1 0 0\n0 0 1 0\n0 0 0 1\n' >"$1.def"
}
scaled_octa() { # stem factor: the octahedron with coordinates and translation scaled; vertices 0, 1, 5 fixed
  # (TF needs constraints off one line), 4 the handle
  write_off "$1.off" 6 8 "$(echo "$octa_v" | awk -v k="$2" '{printf "%.17g %.17g %.17g\n", $1*k, $2*k, $3*k}')" "$octa_f"
  edit_for "$1" 6
  printf '0\n0\n1\n1\n2\n0\n' >"$1.sel"
  awk -v k="$2" 'NR==1{printf "1 0 0 %.17g\n", 0.1*k; next} {print}' "$1.def" >"$1.tmp" && mv "$1.tmp" "$1.def"
}
write_edit() { # file roi handle [transform]
  printf 'mesh = good.off\nroi = %s\nhandle = %s\ntransform = %s\n' "$2" "$3" "${4:-translate:0,0,0.1}" >"$1"
}

write_off "$T/good.off" 6 8 "$octa_v" "$octa_f"; edit_for "$T/good" 6
printf '4\n' >"$T/handle.txt"
G=$T/good
OUT=$O/out.ply

echo "== runs that must succeed"
expect_ok valid_stem out.ply -- deform "$G" --out "$OUT"
expect_ok valid_with_csv "out.ply r.csv" -- deform "$G" --out "$OUT" --csv "$O/r.csv"
expect_ok valid_stl out.stl -- deform "$G" --out "$O/out.stl"  # every format write_mesh knows, STL included
printf '2 3 4\n' >"$T/roi_tf.txt"
write_edit "$T/good.edit" indices:roi_tf.txt indices:handle.txt
expect_ok valid_edit_file out.ply -- deform "$T/good.edit" --method tf --frames 3 --out "$OUT"
expect_ok handle_frames out.ply -- deform "$T/good.edit" --method tf --frames 3 --frame-mode handle --out "$OUT"
write_drag() { # file targets-file: good.edit's selection, the handle (vertex 4) dragged per vertex
  printf 'mesh = good.off\nroi = indices:roi_tf.txt\nhandle = indices:handle.txt\ntargets = %s\n' "$2" >"$1"
}
printf '0 0 1.1\n0 0.1 1.2\n' >"$T/drag.txt"   # two frames of the one handle vertex
write_drag "$T/drag.edit" drag.txt
expect_ok drag_full out.ply -- deform "$T/drag.edit" --method tf --out "$OUT"
expect_ok drag_handle out.ply -- deform "$T/drag.edit" --method tf --frame-mode handle --handle-limit 1e6 --frames 5 --out "$OUT"
expect_ok budget_scientific out.ply -- deform "$G" --memory-budget-mb 1e3 --out "$OUT"  # 1000 MB (issue 28)
expect_ok frames_scientific out.ply -- deform "$G" --frames 2.5e1 --out "$OUT"
expect_ok mixed_precision "out.ply r.csv" -- deform "$G" --precision mixed --vs-double --out "$OUT" --csv "$O/r.csv"
expect_ok cg_tolerance out.ply -- deform "$G" --solver cg_jacobi --cg-tolerance 1e-12 --out "$OUT"
# The reference listing (`deformbench deform-options`, derived from the options' table) has every option of the
# table that `deform --help` shows; the command's own options (edit, outputs, frames, transform, progress) are not in it.
listing=$("$BIN" deform-options)
for f in $("$BIN" deform --help | grep -oE '^  --[a-z-]+'); do
  case $f in --help | --out | --csv | --frames | --transform | --vs-double | --progress) continue ;; esac
  if grep -qF -- "\`$f\`" <<<"$listing"; then passes=$((passes + 1)); else fails=$((fails + 1)); echo "FAIL deform-options lacks $f"; fi
done
for k in 1e200 1e-300; do
  scaled_octa "$T/s$k" "$k"
  for m in lap tf; do expect_ok "scaled_${k}_$m" out.ply -- deform "$T/s$k" --method "$m" --out "$OUT"; done
done

echo "== 1 usage: the command line"
expect typo_frame 1 "unknown option --frame .*did you mean --frames" -- deform "$G" --out "$OUT" --frame 20
expect typo_method 1 "unknown option --metod" -- deform "$G" --metod tf --out "$OUT"
expect frames_fraction 1 "--frames: 2.5 is not a whole number" -- deform "$G" --out "$OUT" --frames 2.5
expect frames_1e10 1 "--frames: 1e10 is outside \[1, 100000\]" -- deform "$G" --out "$OUT" --frames 1e10
expect frames_nan 1 "--frames: nan is not a whole number" -- deform "$G" --out "$OUT" --frames nan
expect frames_negative 1 "--frames: -1 is outside \[1, 100000\]" -- deform "$G" --out "$OUT" --frames -1
expect frames_over_cap 1 "--frames: 100001 is outside \[1, 100000\]" -- deform "$G" --out "$OUT" --frames 100001
expect soft_weight_nan 1 "--soft-weight: nan is not a finite number" -- deform "$G" --out "$OUT" --constraints soft --soft-weight nan
expect unknown_method 1 "--method: 'nope' is not one of: lap, tf, lri" -- deform "$G" --method nope --out "$OUT"
expect unknown_frame_mode 1 "--frame-mode: 'fast' is not one of: full, handle" -- deform "$G" --frame-mode fast --out "$OUT"
expect unknown_solver 1 "--solver: 'nope' is not one of" -- deform "$G" --solver nope --out "$OUT"
expect unknown_ordering 1 "--ordering: 'rcm' is not one of" -- deform "$G" --ordering rcm --out "$OUT"
expect unknown_command 1 "unknown command 'deforn'" -- deforn "$G" --out "$OUT"
expect missing_out 1 "--out is required" -- deform "$G"
expect extra_argument 1 "unexpected argument" -- deform "$G" "$G" --out "$OUT"
expect bad_transform_spec 1 "--transform: transform 'rotate:90'" -- deform "$G" --out "$OUT" --transform rotate:90

echo "== 1 usage: an option the method, constraints or backend does not use"
expect weights_with_lri 1 "--weights is not used by --method lri" -- deform "$G" --method lri --weights cotan --out "$OUT"
expect tf_option_with_lap 1 "--tf-no-translation is for --method tf only" -- deform "$G" --tf-no-translation --out "$OUT"
expect tf_scale_with_lri 1 "--tf-scale is for --method tf only, not lri" -- deform "$G" --method lri --tf-scale normalized --out "$OUT"
expect tf_scale_unknown 1 "--tf-scale" -- deform "$G" --method tf --tf-scale isotropic --out "$OUT"
expect tf_scale_handle_frames 1 "--frame-mode handle with --tf-scale normalized" -- deform "$G" --method tf --tf-scale normalized --frame-mode handle --out "$OUT"
expect lri_option_with_tf 1 "--lri-frames is for --method lri only" -- deform "$G" --method tf --lri-frames random --out "$OUT"
expect refine_without_mixed 1 "--refine-tolerance is for the refined backends only" -- deform "$G" --refine-tolerance 1e-8 --out "$OUT"
expect mixed_other_backend 1 "--precision mixed is the multifrontal backend's" -- deform "$G" --precision mixed --solver cholmod_supernodal --out "$OUT"
expect mixed_iteration_cap 3 "did not reach a relative correction of 1e-14 \(the iteration cap, 0" -- deform "$G" --precision mixed --refine-tolerance 1e-14 --refine-max-iterations 0 --out "$OUT"
expect lri_seed_without_random 1 "--lri-seed is used by --lri-frames random only" -- deform "$G" --method lri --lri-seed 3 --out "$OUT"
expect lri_frame_control_not_lri 1 "--lri-frame-control is for --method lri only" -- deform "$G" --method tf --lri-frame-control uncoordinated --out "$OUT"
expect lri_frame_control_bad 1 "lri-frame-control" -- deform "$G" --method lri --lri-frame-control sideways --out "$OUT"
expect soft_weight_with_hard 1 "--soft-weight .*needs --constraints soft" -- deform "$G" --soft-weight 2 --out "$OUT"
expect factor_dir_with_umfpack 1 "--factor-dir: umfpack cannot keep its factor out of core" -- deform "$G" --solver umfpack --factor-dir "$T" --out "$OUT"
expect cg_tolerance_not_iterative 1 "--cg-tolerance is for the iterative backends only" -- deform "$G" --cg-tolerance 1e-8 --out "$OUT"
expect cg_tolerance_range 1 "--cg-tolerance: 1 is outside" -- deform "$G" --solver cg_jacobi --cg-tolerance 1 --out "$OUT"
expect ordering_not_accepted 1 "--ordering nesdis is not accepted by umfpack" -- deform "$G" --solver umfpack --build naive --ordering nesdis --out "$OUT"
expect ordering_with_dense 1 "--ordering does not apply to --build dense" -- deform "$G" --build dense --ordering amd --out "$OUT"
expect dense_with_sparse_solver 1 "--build dense needs a dense backend" -- deform "$G" --build dense --solver cholmod_supernodal --out "$OUT"
expect lri_dense 1 "--build dense: lri offers" -- deform "$G" --method lri --build dense --out "$OUT"

expect handle_limit_full 1 "--handle-limit bounds handle-mode responses; it needs --frame-mode handle" -- deform "$T/drag.edit" --handle-limit 2 --out "$OUT"
expect handle_limit_affine 1 "--handle-limit bounds the responses of per-vertex targets, but edit 'good' drags its handle by one affine transform" -- deform "$T/good.edit" --method tf --frame-mode handle --handle-limit 2 --out "$OUT"
expect budget_fraction 1 "--memory-budget-mb: 1.5e0 is not a whole number" -- deform "$G" --memory-budget-mb 1.5e0 --out "$OUT"
expect transform_with_targets 1 "--transform replaces the handle transform, but edit 'drag' drags per-vertex targets" -- deform "$T/drag.edit" --transform translate:0,0,1 --out "$OUT"

echo "== 1 usage: outputs, checked before any mesh is read"
expect out_missing_dir 1 "directory .* does not exist" -- deform "$G" --out "$O/no/such/dir/out.ply"
expect out_before_input 1 "directory .* does not exist" -- deform "$T/nothere" --out "$O/no/out.ply"
expect out_bad_extension 1 "unsupported extension '.vtk'" -- deform "$G" --out "$O/out.vtk"
mkdir -p "$T/dir.ply"
expect out_is_a_directory 1 "is a directory" -- deform "$G" --out "$T/dir.ply"
expect out_is_the_input 1 "is an input file" -- deform "$G" --out "$G.off"
expect out_is_the_input_respelled 1 "is an input file" -- deform "$G" --out "$T/./outdir/../good.off"
expect out_is_the_edit_mesh 1 "is an input file" -- deform "$T/good.edit" --out "$T/good.off"
expect csv_missing_dir 1 "--csv .*does not exist" -- deform "$G" --out "$OUT" --csv "$O/no/such/dir/r.csv"
expect csv_bad_extension 1 "--csv .*unsupported extension '.txt'" -- deform "$G" --out "$OUT" --csv "$O/r.txt"
expect csv_under_a_file 1 "--csv .*is not a directory" -- deform "$G" --out "$OUT" --csv "$G.off/r.csv"
OOC=$("$BIN" solvers | awk '/--factor-dir/ {print $1; exit}')  # an out-of-core backend
expect factor_dir_missing 1 "--factor-dir: directory .* does not exist" -- deform "$G" --out "$OUT" --solver "$OOC" --factor-dir "$T/nodir"
expect factor_dir_is_a_file 1 "--factor-dir: '.*good.off' is not a directory" -- deform "$G" --out "$OUT" --solver "$OOC" --factor-dir "$G.off"
if [ "$(id -u)" -ne 0 ]; then # root writes anywhere
  mkdir -p "$T/ro" && chmod 555 "$T/ro"
  expect csv_read_only_dir 1 "--csv .*not writable" -- deform "$G" --out "$OUT" --csv "$T/ro/r.csv"
fi

# An immutable target cannot be replaced: refused before the solve (root with a file system that takes chattr +i).
: >"$L/imm.ply"
if chattr +i "$L/imm.ply" 2>/dev/null; then
  expect out_immutable 1 "--out .*imm.ply: cannot be replaced \(Operation not permitted: immutable" -- deform "$G" --out "$L/imm.ply"
  chattr -i "$L/imm.ply"
else echo "skip out_immutable: chattr +i not permitted here"; fi
# An append-only directory takes the temporary but not the rename that puts it in place: refused before the solve.
mkdir -p "$L/app"
if chattr +a "$L/app" 2>/dev/null; then
  expect out_append_only_dir 1 "--out .*app/out.ply: directory .* is append-only" -- deform "$G" --out "$L/app/out.ply"
  [ -z "$(ls -A "$L/app")" ] || { fails=$((fails + 1)); echo "FAIL out_append_only_dir: left $(ls "$L/app")"; }
  chattr -a "$L/app"
else echo "skip out_append_only_dir: chattr +a not permitted here"; fi
# The kernel's file systems take no output, whatever access() says (root; others are refused as not writable):
# refused before the solve.
expect out_in_proc 1 "--out /proc/out.ply: directory '/proc' is (on the kernel's proc file system|not writable)" -- deform "$G" --out /proc/out.ply
expect csv_in_sys 1 "--csv /sys/r.csv: directory '/sys' is (on the kernel's sysfs file system|not writable)" -- deform "$G" --out "$OUT" --csv /sys/r.csv
# export-system's two outputs cannot be one file, however spelled.
echo earlier >"$L/k.mtx"
expect export_same_file 1 "--out .*k.mtx and --rhs .*k.mtx name the same file" -- export-system "$G" --out "$L/k.mtx" --rhs "$L/./k.mtx"
[ "$(cat "$L/k.mtx")" = earlier ] && [ "$(ls "$L" | grep -c '^k\.')" -eq 1 ] && passes=$((passes + 1)) &&
  echo "ok   export_same_file: the earlier file is unchanged" || { fails=$((fails + 1)); echo "FAIL export_same_file: $(ls "$L")"; }
# A full file system is found before the solve (root: a tiny tmpfs in a private mount namespace).
mkdir -p "$L/full"
if unshare -m true 2>/dev/null; then
  msg=$(unshare -m sh -c 'mount -t tmpfs -o size=64k none "$1" && { dd if=/dev/zero of="$1/fill" bs=4k 2>/dev/null; exec timeout 20 "$2" deform "$3" --out "$1/out.ply"; }' \
    sh "$L/full" "$BIN" "$G" 2>&1)
  code=$?
  if [ "$code" -eq 1 ] && grep -q "directory '.*full' is full (No space left on device)" <<<"$msg"; then passes=$((passes + 1)); echo "ok   disk_full (1): $msg"
  else fails=$((fails + 1)); echo "FAIL disk_full: exit $code: $msg"; fi
else echo "skip disk_full: no private mount namespace here"; fi
# A write that fails names the target once and the cause (a file size limit: EFBIG, as ENOSPC would be).
msg=$( (trap '' XFSZ; ulimit -f 0; exec timeout 20 "$BIN" deform "$G" --out "$OUT") 2>&1 >/dev/null)
code=$?
if [ "$code" -ne 0 ] && grep -q "cannot write $OUT: File too large" <<<"$msg" && ! grep -q "\.tmp\.[0-9]" <<<"$msg" && [ -z "$(ls -A "$O")" ]; then
  passes=$((passes + 1)); echo "ok   write_fails ($code): $msg"
else fails=$((fails + 1)); echo "FAIL write_fails: exit $code, left '$(ls -A "$O")': $msg"; rm -rf "${O:?}"/*; fi
# The same without the caller ignoring SIGXFSZ: the tool ignores it itself (solvers/base/cleanup.h), so the limit
# is a failed write, not a kill that leaves the temporary behind.
msg=$( (ulimit -f 0; exec timeout 20 "$BIN" deform "$G" --out "$OUT") 2>&1 >/dev/null)
code=$?
if [ "$code" -eq 1 ] && grep -q "cannot write $OUT: File too large" <<<"$msg" && [ -z "$(ls -A "$O")" ]; then
  passes=$((passes + 1)); echo "ok   file_size_limit ($code): $msg"
else fails=$((fails + 1)); echo "FAIL file_size_limit: exit $code, left '$(ls -A "$O")': $msg"; rm -rf "${O:?}"/*; fi

echo "== 2 bad input: special and oversized files, refused before they are read (issue 28)"
mkfifo "$T/fifo.edit" "$T/fifo.txt" "$T/fifo.def"
expect fifo_edit 2 "cannot open edit file: .*fifo.edit \(not a regular file" -- deform "$T/fifo.edit" --out "$OUT"
write_drag "$T/drag_fifo.edit" fifo.txt
expect fifo_targets 2 "cannot open targets file: .*fifo.txt \(not a regular file" -- deform "$T/drag_fifo.edit" --out "$OUT"
write_edit "$T/fifo_indices.edit" indices:fifo.txt indices:handle.txt
expect fifo_indices 2 "cannot open index list file: .*fifo.txt \(not a regular file" -- deform "$T/fifo_indices.edit" --out "$OUT"
write_edit "$T/fifo_def.edit" indices:roi_tf.txt indices:handle.txt def:fifo.def
expect fifo_def 2 "cannot open transform file: .*fifo.def \(not a regular file" -- deform "$T/fifo_def.edit" --out "$OUT"
expect fifo_transform 2 "cannot open transform file: .*fifo.def \(not a regular file" -- deform "$G" --transform "def:$T/fifo.def" --out "$OUT"
rm -f "$T"/fifo.*
# 2 GB sparse files (zeros, no line end): refused by their size or at line 1 after a bounded read (a text
# reader stops at the first NUL byte, a mesh reader at its line bound), never read whole.
# They lie outside $T, whose files every case checksums.
truncate -s 2G "$L/sparse.edit" "$L/sparse.txt" "$L/sparse.off" "$L/sparse.idx"
expect sparse_edit 2 "edit file .*sparse.edit holds 2147483648 bytes, more than such a file can sensibly hold" -- deform "$L/sparse.edit" --out "$OUT"
printf 'mesh = %s\nroi = indices:%s\nhandle = indices:%s\ntargets = %s\n' "$T/good.off" "$T/roi_tf.txt" "$T/handle.txt" "$L/sparse.txt" >"$L/sparse_targets.edit"
expect sparse_targets 2 "sparse.txt: line 1: holds a NUL byte" -- deform "$L/sparse_targets.edit" --out "$OUT"
printf 'mesh = %s\nroi = indices:%s\nhandle = indices:%s\ntransform = translate:0,0,1\n' "$T/good.off" "$L/sparse.idx" "$T/handle.txt" >"$L/sparse_indices.edit"
expect sparse_indices 2 "index list file .*sparse.idx holds 2147483648 bytes, more than" -- deform "$L/sparse_indices.edit" --out "$OUT"
printf 'mesh = %s\nroi = indices:%s\nhandle = indices:%s\ntransform = translate:0,0,1\n' "$L/sparse.off" "$T/roi_tf.txt" "$T/handle.txt" >"$L/sparse_mesh.edit"
expect sparse_mesh 2 "sparse.off: line 1: longer than 65536 bytes \(not a mesh file\)" -- deform "$L/sparse_mesh.edit" --out "$OUT"
expect sparse_over_budget 4 "input files of edit .* hold 2147.* MB, more than --memory-budget-mb 100" -- deform "$L/sparse_mesh.edit" --memory-budget-mb 100 --out "$OUT"
rm -f "$L"/sparse*
# A targets file's frames are capped as --frames is: 100001 frames of the one handle vertex.
awk 'BEGIN { for (i = 0; i < 100001; i++) print "0 0 1.1" }' >"$T/drag_long.txt"; write_drag "$T/drag_long.edit" drag_long.txt
expect targets_over_frames_cap 2 "drag_long.txt: line 100001: more than 100000 target positions \(100000 frames" -- deform "$T/drag_long.edit" --out "$OUT"
# A long drag says how far it is (--progress; on by default on a terminal): here after every frame, one line each
# (stderr is no terminal); without --progress, nothing.
awk 'BEGIN { for (i = 0; i < 5; i++) print "0 0 1.1" }' >"$T/drag_five.txt"; write_drag "$T/drag_five.edit" drag_five.txt
export DEFORMBENCH_PROGRESS_SECONDS=0
progress_re='^deform: frame [1-5]/5 \([0-9.]+%\), [0-9]+ s elapsed, about [0-9]+ s left$'
expect_ok targets_progress out.ply -- deform "$T/drag_five.edit" --progress --out "$OUT"
if [ "$(grep -Ec "$progress_re" "$L/stderr")" = 5 ] && grep -q '^deform: frame 5/5 (100.0%)' "$L/stderr"; then
  passes=$((passes + 1)); echo "ok   targets_progress: 5 progress lines"
else fails=$((fails + 1)); echo "FAIL targets_progress: not 5 progress lines:"; cat "$L/stderr"; fi
expect_ok targets_no_progress out.ply -- deform "$T/drag_five.edit" --out "$OUT"
if grep -q 'deform: frame' "$L/stderr"; then fails=$((fails + 1)); echo "FAIL targets_no_progress: progress printed"
else passes=$((passes + 1)); echo "ok   targets_no_progress: none printed"; fi
unset DEFORMBENCH_PROGRESS_SECONDS

echo "== 2 bad input: mesh and edit files"
expect missing_mesh 2 "cannot open|not found|no such|missing" -- deform "$T/nothere" --out "$OUT"
printf 'OFF\n6 8 0\n1 0 0\n-1 0\n' >"$T/trunc.off"; cp "$G.sel" "$T/trunc.sel"; cp "$G.def" "$T/trunc.def"
expect truncated_off 2 "trunc" -- deform "$T/trunc" --out "$OUT"
printf 'OFF\n6 8 0\n1 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0 0 1\n0 0 -1\n3 0 2 4\n3 2 1 4\n3 1 3 4\n3 3 0 4\n3 2 0 5\n3 1 2 5\n3 3 1 5\n3 0 3 9\n' >"$T/range.off"; cp "$G.sel" "$T/range.sel"; cp "$G.def" "$T/range.def"
expect index_out_of_range 2 "range|index" -- deform "$T/range" --out "$OUT"
write_off "$T/nan.off" 6 8 "1 0 0
-1 0 0
0 nan 0
0 -1 0
0 0 1
0 0 -1" "$octa_f"; cp "$G.sel" "$T/nan.sel"; cp "$G.def" "$T/nan.def"
expect nan_coordinates 2 "finite|nan" -- deform "$T/nan" --out "$OUT"
write_off "$T/iso.off" 7 8 "$octa_v
3 3 3" "$octa_f"; edit_for "$T/iso" 7
expect isolated_vertex 2 "isolated" -- deform "$T/iso" --out "$OUT"
write_off "$T/degen.off" 6 9 "$octa_v" "$octa_f
3 0 0 1"; cp "$G.sel" "$T/degen.sel"; cp "$G.def" "$T/degen.def"
expect degenerate_face 2 "degenerate" -- deform "$T/degen" --out "$OUT"
# Three faces on one edge: a fin glued to edge 0-2 of the octahedron. Cotan weights need a manifold 1-ring.
write_off "$T/nm.off" 7 9 "$octa_v
2 2 0" "$octa_f
3 0 6 2"; edit_for "$T/nm" 7
# Uniform lap and tf deform it with a warning that counts the non-manifold elements; cotan and lri refuse it.
expect_ok non_manifold_lap out.ply -- deform "$T/nm" --out "$OUT"
grep -q "1 non-manifold edge" "$L/stderr" || { echo "FAIL non_manifold_lap: no warning"; fails=$((fails + 1)); }
# TF needs three constrained vertices off one line: vertex 0 fixed too.
cp "$T/nm.off" "$T/nmtf.off"; cp "$T/nm.def" "$T/nmtf.def"; sed '1s/.*/0/' "$T/nm.sel" >"$T/nmtf.sel"
expect_ok non_manifold_tf out.ply -- deform "$T/nmtf" --method tf --out "$OUT"
expect non_manifold_lri 2 "not manifold.*meshtool repair" -- deform "$T/nm" --method lri --out "$OUT"
expect non_manifold_cotan 2 "not manifold.*meshtool repair" -- deform "$T/nm" --weights cotan --out "$OUT"
# export-system builds the deformer's systems: the same check, message and exit code.
expect export_non_manifold_lri 2 "not manifold.*meshtool repair" -- export-system "$T/nm" --method lri --out "$O/k.mtx"
expect export_non_manifold_cotan 2 "not manifold.*meshtool repair" -- export-system "$T/nm" --weights cotan \
  --out "$O/k.mtx"
cp "$G.off" "$T/short.off"; head -3 "$G.sel" >"$T/short.sel"; cp "$G.def" "$T/short.def"
expect selection_size_mismatch 2 "entries|vertices" -- deform "$T/short" --out "$OUT"
cp "$G.off" "$T/nohandle.off"; printf '1\n1\n1\n1\n1\n0\n' >"$T/nohandle.sel"; cp "$G.def" "$T/nohandle.def"
expect empty_handle_sel 2 "handle is empty" -- deform "$T/nohandle" --out "$OUT"
expect transform_file_missing 2 "cannot open transform file" -- deform "$G" --out "$OUT" --transform "def:$T/none.def"
scaled_octa "$T/huge" 1e308
expect coordinates_overflow 2 "vertices 1 and 0 \\(their x coordinates .*\\) lie farther apart than a double can measure" -- deform "$T/huge" --out "$OUT"

echo "== 2 bad input: per-vertex targets"
printf '0 0 1.1\n0 nan 1.2\n' >"$T/drag_nan.txt"; write_drag "$T/drag_nan.edit" drag_nan.txt
expect targets_nan 2 "drag_nan.txt: line 2: bad number 'nan'" -- deform "$T/drag_nan.edit" --out "$OUT"
printf '0 0 1.1\n0 0\0001.2\n' >"$T/drag_nul.txt"; write_drag "$T/drag_nul.edit" drag_nul.txt
expect targets_nul 2 "drag_nul.txt: line 2: holds a NUL byte \(a binary file, not a targets file\?\)" -- deform "$T/drag_nul.edit" --out "$OUT"
printf '0 0 1.1 3\n' >"$T/drag_4.txt"; write_drag "$T/drag_4.edit" drag_4.txt
expect targets_four_numbers 2 "drag_4.txt: line 1: expected 3 numbers \(x y z\), got 4" -- deform "$T/drag_4.edit" --out "$OUT"
printf '3 4\n' >"$T/handle2.txt"
printf 'mesh = good.off\nroi = indices:roi_tf.txt\nhandle = indices:handle2.txt\ntargets = drag3.txt\n' >"$T/drag3.edit"
printf '0 0 1\n0 0 1\n0 0 1\n' >"$T/drag3.txt"
expect targets_count 2 "3 target positions are not a whole number of frames of the handle's 2 vertices" -- deform "$T/drag3.edit" --out "$OUT"
: >"$T/drag_empty.txt"; write_drag "$T/drag_empty.edit" drag_empty.txt
expect targets_empty 2 "drag_empty.txt: no target positions" -- deform "$T/drag_empty.edit" --out "$OUT"
write_drag "$T/drag_missing.edit" nothere.txt
expect targets_missing 2 "cannot open targets file" -- deform "$T/drag_missing.edit" --out "$OUT"
expect targets_lri 2 "per-vertex handle targets .* need --method lap or tf" -- deform "$T/drag.edit" --method lri --out "$OUT"

echo "== 2 bad input: selections name their cause"
printf '0 1 2\n' >"$T/roi.txt"
printf 'mesh = good.off\nroi = indices:roi.txt\nhandle = indices:handle.txt\ntransform = translate:0,0,1\n' >"$T/outside.edit"
expect handle_outside_roi 2 "handle vertex 4 is outside the region of interest" -- deform "$T/outside.edit" --out "$OUT"
write_edit "$T/e1.edit" sphere:9,9,9,0.5 indices:handle.txt
expect empty_roi 2 "roi selection 'sphere:9,9,9,0.5' selects no vertex" -- deform "$T/e1.edit" --out "$OUT"
write_edit "$T/e2.edit" all box:5,5,5,6,6,6
expect empty_handle 2 "handle selection 'box:5,5,5,6,6,6' selects no vertex" -- deform "$T/e2.edit" --out "$OUT"
write_edit "$T/e3.edit" box:1,1,1,-1,-1,-1 indices:handle.txt
expect inverted_box 2 "box: inverted in x" -- deform "$T/e3.edit" --out "$OUT"
write_edit "$T/e4.edit" sphere:0,0,0,-1 indices:handle.txt
expect negative_radius 2 "radius -1 is negative" -- deform "$T/e4.edit" --out "$OUT"
write_edit "$T/e5.edit" kring:99,1 indices:handle.txt
expect kring_bad_vertex 2 "seed vertex 99 out of range" -- deform "$T/e5.edit" --out "$OUT"
write_edit "$T/e6.edit" kring:4,-1 indices:handle.txt
expect kring_negative_k 2 "k must be >= 0" -- deform "$T/e6.edit" --out "$OUT"
write_edit "$T/e6b.edit" kring:4,4000000000 indices:handle.txt
expect kring_k_out_of_range 2 "k 4000000000 is out of range" -- deform "$T/e6b.edit" --out "$OUT"
# A UTF-8 byte-order mark before the first key is no part of it.
write_edit "$T/plain.edit" kring:4,1 indices:handle.txt
{ printf '\xEF\xBB\xBF'; cat "$T/plain.edit"; } >"$T/bom.edit"
expect_ok edit_with_bom out.ply -- deform "$T/bom.edit" --out "$OUT"
write_edit "$T/e7.edit" all nearest:0,0,1,0
expect nearest_zero 2 "count 0 must be in \[1, 6\]" -- deform "$T/e7.edit" --out "$OUT"
write_edit "$T/e8.edit" all nearest:0,0,1,7
expect nearest_too_many 2 "count 7 must be in \[1, 6\]" -- deform "$T/e8.edit" --out "$OUT"
write_edit "$T/e9.edit" indices:handle.txt indices:handle.txt
expect roi_only_handle 2 "no free vertex" -- deform "$T/e9.edit" --out "$OUT"
# Two octahedra, the constraints only on the first: the second is a free component with no anchor.
write_off "$T/two.off" 12 16 "$octa_v
11 0 0
9 0 0
10 1 0
10 -1 0
10 0 1
10 0 -1" "$octa_f
3 6 8 10
3 8 7 10
3 7 9 10
3 9 6 10
3 8 6 11
3 7 8 11
3 9 7 11
3 6 9 11"; edit_for "$T/two" 12
expect singular_roi 2 "singular" -- deform "$T/two" --out "$OUT"

echo "== 4 over budget"
# Three guards: the build's size, the default backend's own check of its factor once its analysis knows it, and
# for the other backends the run's predicted peak before anything is built.
expect over_build_budget 4 "structured build of the tf system needs about .* MB, over the budget of 1.0 MB" -- deform "$SRC/data/bs08/bar" --method tf --memory-budget-mb 1 --out "$OUT" --csv "$O/r.csv"
expect over_factor_budget 4 "multifrontal: the factor \(.* MB\) and its update matrices \(up to .* MB\) beside the .* MB this process holds would pass the memory budget of 8.0 MB; not factored" -- deform "$SRC/data/bs08/bar" --method tf --memory-budget-mb 8 --out "$OUT" --csv "$O/r.csv"
expect over_memory_budget 4 "predicted to peak at .* MB .*over --memory-budget-mb 8; not started" -- deform "$SRC/data/bs08/bar" --method tf --solver cholmod_supernodal --memory-budget-mb 8 --out "$OUT" --csv "$O/r.csv"

echo "$passes passed, $fails failed"
[ "$fails" -eq 0 ]
