#!/usr/bin/env bash
# `deformbench coat` and `deformbench transplant` on small meshes: a run that works writes the mesh and the CSV;
# bad input (a patch that is no disk, an empty patch, a patch with no interior vertex, a region naming vertices the
# mesh does not have) is exit 2 with a message naming the cause (and what the region selects) and no file left
# behind; options out of range or for the other command exit 1.
# usage: cli_applications.sh PATH/TO/deformbench
BIN=$1
source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"  # $T, expect, the octahedron, write_off

# A 4 x 4 grid of squares (25 vertices), each split into two triangles: a disk with interior vertices.
grid_v=$(for j in 0 1 2 3 4; do for i in 0 1 2 3 4; do echo "$i $j $(( (i * j) % 3 ))"; done; done)
grid_f=$(for j in 0 1 2 3; do for i in 0 1 2 3; do a=$((j * 5 + i)); echo "3 $a $((a + 1)) $((a + 6))"; echo "3 $a $((a + 6)) $((a + 5))"; done; done)
write_off "$T/grid.off" 25 32 "$grid_v" "$grid_f"
write_off "$T/octa.off" 6 8 "$octa_v" "$octa_f"
# An open tube: two rings of four vertices, two boundary loops (an annulus).
tube_v='1 0 0
0 1 0
-1 0 0
0 -1 0
1 0 1
0 1 1
-1 0 1
0 -1 1'
tube_f=$(for k in 0 1 2 3; do n=$(((k + 1) % 4)); echo "3 $k $n $((n + 4))"; echo "3 $k $((n + 4)) $((k + 4))"; done)
write_off "$T/tube.off" 8 8 "$tube_v" "$tube_f"
printf '0\n1\n99\n' >"$T/far.txt"
# A strip of four triangles along the grid's edge (7 vertices, 6 in its faces): a disk with every vertex on its
# boundary, nothing inside for the LSE solve to move; trimmed of its ears one after the other (transplant), no face
# is left.
printf '0\n1\n2\n3\n5\n6\n7\n' >"$T/strip.txt"

for cmd in coat transplant; do
  expect "$cmd runs" 0 "detail_error" -- $cmd "$T/grid.off" "$T/grid.off" --out "$T/out.ply" --csv "$T/out.csv"
  [ -s "$T/out.ply" ] && [ -s "$T/out.csv" ] && grep -q "^app,source,target" "$T/out.csv" &&
    { passes=$((passes + 1)); echo "ok   $cmd wrote the mesh and the CSV"; } ||
    { fails=$((fails + 1)); echo "FAIL $cmd: out.ply / out.csv missing or without header"; }
  # A measurement that does not apply (transplant: the coating's amplitude) is an empty cell, never "nan".
  ! grep -qiw nan "$T/out.csv" "$T/message" && { passes=$((passes + 1)); echo "ok   $cmd wrote no nan"; } ||
    { fails=$((fails + 1)); echo "FAIL $cmd: nan in its output: $(grep -iw nan "$T/out.csv" "$T/message")"; }
  expect "$cmd closed target" 2 "target patch is not a disk: it has no boundary" -- $cmd "$T/grid.off" "$T/octa.off" --out "$T/out.ply"
  expect "$cmd annulus source" 2 "source patch is not a disk: .*more than one loop" -- $cmd "$T/tube.off" "$T/grid.off" --out "$T/out.ply"
  expect "$cmd empty patch" 2 "target region holds no whole face.*empty" -- $cmd "$T/grid.off" "$T/grid.off" --target-region kring:12,0 --out "$T/out.ply"
  expect "$cmd region selects nothing" 2 "--source-region sphere:50,50,50,1 selects no vertex" -- $cmd "$T/grid.off" "$T/grid.off" --source-region sphere:50,50,50,1 --out "$T/out.ply"
  expect "$cmd region index beyond the mesh" 2 "99" -- $cmd "$T/grid.off" "$T/grid.off" --source-region "indices:$T/far.txt" --out "$T/out.ply"
  expect "$cmd missing mesh" 2 "nothere" -- $cmd "$T/nothere.off" "$T/grid.off" --out "$T/out.ply"
  expect "$cmd output extension" 1 "extension" -- $cmd "$T/grid.off" "$T/grid.off" --out "$T/out.txt"
  expect "$cmd output over an input" 1 "input" -- $cmd "$T/grid.off" "$T/octa.off" --out "$T/grid.off"
done
expect "coat onto a patch without interior" 2 "target patch has no interior vertex \(all 6 of its vertices" -- coat "$T/grid.off" "$T/grid.off" --target-region "indices:$T/strip.txt" --out "$T/out.ply"
expect "coat from a patch without interior" 2 "source patch has no interior vertex" -- coat "$T/grid.off" "$T/grid.off" --source-region "indices:$T/strip.txt" --out "$T/out.ply"
expect "transplant counts the selection before trimming" 2 "target region holds no whole face of grid once its ears are trimmed \(7 vertices selected\)" -- transplant "$T/grid.off" "$T/grid.off" --target-region "indices:$T/strip.txt" --out "$T/out.ply"
expect "coat with another map and encoding" 0 "detail_error" -- coat "$T/grid.off" "$T/grid.off" --map mean-value --encoding laplacian --out "$T/out.ply"
expect "coat unknown map" 1 "map" -- coat "$T/grid.off" "$T/grid.off" --map tutte --out "$T/out.ply"
expect "coat unknown encoding" 1 "encoding" -- coat "$T/grid.off" "$T/grid.off" --encoding normal --out "$T/out.ply"
expect "coat smooth weight out of range" 1 "smooth-weight" -- coat "$T/grid.off" "$T/grid.off" --smooth-weight 0 --out "$T/out.ply"
expect "coat refuses --zone" 1 "zone" -- coat "$T/grid.off" "$T/grid.off" --zone 0.3 --out "$T/out.ply"
expect "transplant zone out of range" 1 "zone" -- transplant "$T/grid.off" "$T/grid.off" --zone 2 --out "$T/out.ply"
expect "transplant refuses --amplitude" 1 "amplitude" -- transplant "$T/grid.off" "$T/grid.off" --amplitude 2 --out "$T/out.ply"

echo "$passes passed, $fails failed"
((fails == 0))
