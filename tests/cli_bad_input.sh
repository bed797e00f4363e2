#!/usr/bin/env bash
# Bad input through the command line: a clear message naming the problem, a non-zero exit code, and no
# output file. usage: cli_bad_input.sh PATH/TO/deformbench
BIN=$1
source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"

edit_for() { # stem: write STEM.sel (handle=4, fixed=5, rest free) and an identity-ish .def
  local n=$2
  { for ((i = 0; i < n; i++)); do
      if [ $i -eq 4 ]; then echo 2; elif [ $i -eq 5 ]; then echo 0; else echo 1; fi
    done; } >"$1.sel"
  printf '1 0 0 0.1\n0 1 0 0\n0 0 1 0\n0 0 0 1\n' >"$1.def"
}

write_off "$T/good.off" 6 8 "$octa_v" "$octa_f"; edit_for "$T/good" 6
"$BIN" deform "$T/good" --out "$T/good_out.ply" >/dev/null 2>&1 || { echo "FAIL sanity: the valid octahedron edit did not run"; fails=$((fails + 1)); }

expect missing_mesh 2 "cannot open|not found|no such|missing" -- deform "$T/nothere" --out "$T/out.ply"
printf 'OFF\n6 8 0\n1 0 0\n-1 0\n' >"$T/trunc.off"; cp "$T/good.sel" "$T/trunc.sel"; cp "$T/good.def" "$T/trunc.def"
expect truncated_off 2 "trunc" -- deform "$T/trunc" --out "$T/out.ply"
printf 'OFF\n6 8 0\n1 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0 0 1\n0 0 -1\n3 0 2 4\n3 2 1 4\n3 1 3 4\n3 3 0 4\n3 2 0 5\n3 1 2 5\n3 3 1 5\n3 0 3 9\n' >"$T/range.off"; cp "$T/good.sel" "$T/range.sel"; cp "$T/good.def" "$T/range.def"
expect index_out_of_range 2 "range|index" -- deform "$T/range" --out "$T/out.ply"
write_off "$T/nan.off" 6 8 "1 0 0
-1 0 0
0 nan 0
0 -1 0
0 0 1
0 0 -1" "$octa_f"; cp "$T/good.sel" "$T/nan.sel"; cp "$T/good.def" "$T/nan.def"
expect nan_coordinates 2 "finite|nan" -- deform "$T/nan" --out "$T/out.ply"
write_off "$T/iso.off" 7 8 "$octa_v
3 3 3" "$octa_f"; edit_for "$T/iso" 7
expect isolated_vertex 2 "isolated" -- deform "$T/iso" --out "$T/out.ply"
write_off "$T/degen.off" 6 9 "$octa_v" "$octa_f
3 0 0 1"; cp "$T/good.sel" "$T/degen.sel"; cp "$T/good.def" "$T/degen.def"
expect degenerate_face 2 "degenerate" -- deform "$T/degen" --out "$T/out.ply"
# Three faces on one edge: a fin glued to edge 0-2 of the octahedron.
write_off "$T/nm.off" 7 9 "$octa_v
2 2 0" "$octa_f
3 0 6 2"; edit_for "$T/nm" 7
# Uniform lap and tf deform it (with a warning that counts the non-manifold elements); cotan and lri refuse it.
"$BIN" deform "$T/nm" --out "$T/nm_out.ply" >/dev/null 2>"$T/stderr" && grep -q "1 non-manifold edge" "$T/stderr" ||
  { echo "FAIL non_manifold_lap: did not deform with a warning"; cat "$T/stderr"; fails=$((fails + 1)); }
expect non_manifold_lri 2 "not manifold.*meshtool repair" -- deform "$T/nm" --method lri --out "$T/out.ply"
expect non_manifold_cotan 2 "not manifold.*meshtool repair" -- deform "$T/nm" --weights cotan --out "$T/out.ply"
cp "$T/good.off" "$T/short.off"; head -3 "$T/good.sel" >"$T/short.sel"; cp "$T/good.def" "$T/short.def"
expect selection_size_mismatch 2 "entries|vertices" -- deform "$T/short" --out "$T/out.ply"
cp "$T/good.off" "$T/nohandle.off"; printf '1\n1\n1\n1\n1\n0\n' >"$T/nohandle.sel"; cp "$T/good.def" "$T/nohandle.def"
expect empty_handle 2 "handle" -- deform "$T/nohandle" --out "$T/out.ply"
printf 'mesh = good.off\nroi = indices:roi.txt\nhandle = indices:handle.txt\ntransform = translate:0,0,1\n' >"$T/outside.edit"
printf '0 1 2\n' >"$T/roi.txt"; printf '4\n' >"$T/handle.txt"
expect handle_outside_roi 2 "outside" -- deform "$T/outside.edit" --out "$T/out.ply"
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
expect singular_roi 2 "singular" -- deform "$T/two" --out "$T/out.ply"
expect bad_method 2 "method" -- deform "$T/good" --method nope --out "$T/out.ply"
expect missing_out_dir 1 "directory" -- deform "$T/good" --out "$T/no/such/dir/out.ply"

echo "$passes passed, $fails failed"
[ "$fails" -eq 0 ]
