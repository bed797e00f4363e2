#!/usr/bin/env bash
# meshtool on the command line: the exit codes (0 ok, 1 usage, 2 bad input, 4 over the memory budget), a message
# naming the cause, no output file left behind on failure, and refusals that come at once (a subdivision or a
# generated mesh over the budget is refused on its prediction, before anything is allocated).
# usage: meshtool_cli.sh PATH/TO/meshtool
BIN=$1
source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"

# The octahedron, and the same with a fin on edge 0-2 (three faces on one edge) and face 0 given twice.
write_off "$T/good.off" 6 8 "$octa_v" "$octa_f"
write_off "$T/fin.off" 7 10 "$octa_v
2 2 0" "$octa_f
3 0 6 2
3 0 2 4"
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n' >"$T/flat.off"
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 1\n' >"$T/repeated.off"
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nelement junk 1000000000000\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' >"$T/huge.ply"

# Usage (1): the parser's and the validators' messages.
expect no_subcommand 1 "subcommand" --
expect unknown_subcommand 1 "unexpected argument 'smooth'" -- smooth "$T/good.off"
expect levels_fraction 1 "2.5 is not a whole number" -- subdivide "$T/good.off" "$T/out.off" 2.5
expect levels_negative 1 "outside" -- subdivide "$T/good.off" "$T/out.off" -1
expect levels_huge 1 "1e10 is outside" -- subdivide "$T/good.off" "$T/out.off" 1e10
expect budget_zero 1 "outside" -- subdivide "$T/good.off" "$T/out.off" 1 --memory-budget-mb 0
expect misspelled_option 1 "did you mean --max-list" -- repair "$T/fin.off" "$T/out.off" --max-lst 3
expect unknown_shape 1 "not one of" -- generate sphere "$T/out.off"
expect unknown_parameter 1 "unknown parameter 'rows'" -- generate plane "$T/out.off" rows=3
expect bad_parameter 1 "nx: abc is not a whole number" -- generate plane "$T/out.off" nx=abc
expect parameter_range 1 "segments: 2 is outside" -- generate cylinder "$T/out.off" segments=2
expect nan_parameter 1 "radius: nan is not a finite number" -- generate cylinder "$T/out.off" radius=nan
expect twice 1 "given twice" -- generate bar "$T/out.off" nx=2 nx=3
expect not_key_value 1 "expected key=value" -- generate bar "$T/out.off" 3
# Outputs are checked before any input is read.
expect out_extension 1 "unsupported extension '.stp'" -- convert "$T/good.off" "$T/out.stp"
expect stl_encoding 1 "--stl: .*not one of" -- convert "$T/good.off" "$T/out.stl" --stl float
expect out_missing_dir 1 "does not exist" -- repair "$T/good.off" "$T/no/dir/out.off"
expect out_is_input 1 "is an input file" -- repair "$T/good.off" "$T/good.off"
expect out_is_input_spelled 1 "is an input file" -- subdivide "$T/good.off" "$T/./good.off" 1
expect stl_option_not_stl 1 "--stl: OUT .*out.off is not an .stl file" -- convert "$T/good.off" "$T/out.off" --stl binary

# Bad input (2).
expect missing_input 2 "cannot open mesh file" -- info "$T/nothere.off"
mkfifo "$T/fifo.off"  # refused before it is opened: no writer ever comes (issue 28)
expect fifo_input 2 "cannot open mesh file: .*fifo.off \(not a regular file" -- info "$T/fifo.off"
rm -f "$T/fifo.off"
expect huge_element 2 "element 'junk' declares 1000000000000 entries" -- info "$T/huge.ply"
expect validate_non_manifold 2 "non-manifold edge \(0, 2\).*meshtool repair" -- info "$T/fin.off" --validate
expect subdivide_non_manifold 2 "meshtool repair" -- subdivide "$T/fin.off" "$T/out.off" 1
expect repair_nothing_left 2 "no face is left" -- repair "$T/flat.off" "$T/out.off"
# An empty mesh, in the formats that can spell one, and header counts that cannot be.
: >"$T/empty.obj"
printf 'OFF\n0 0 0\n' >"$T/empty.off"
expect empty_obj 2 "empty.obj: the mesh is empty \(no faces\)" -- convert "$T/empty.obj" "$T/out.ply"
expect empty_off 2 "empty.off: the mesh is empty \(no faces\)" -- info "$T/empty.off"
printf 'OFF\n3 1 -1\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' >"$T/edges.off"
expect negative_edge_count 2 "line 2: bad edge count '-1'" -- info "$T/edges.off"
ply_head='ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n'
printf "${ply_head}property double x\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n" >"$T/twice_x.ply"
expect ply_property_twice 2 "line 7: 'vertex' element: property 'x' declared twice" -- info "$T/twice_x.ply"
printf "${ply_head}element vertex 3\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n" >"$T/twice_v.ply"
expect ply_element_twice 2 "line 7: element 'vertex' declared twice \(first on line 3\)" -- info "$T/twice_v.ply"
# STL: a face STL cannot hold is refused before the file is opened; a binary STL cut short is named as such.
expect stl_degenerate_face 2 "cannot write .*out.stl: face 0: corners 1 and 2 are the same point" \
  -- convert "$T/repeated.off" "$T/out.stl"
"$BIN" convert "$T/good.off" "$T/good_bin.stl" --stl binary >/dev/null
head -c 300 "$T/good_bin.stl" >"$T/cut.stl"
expect stl_truncated 2 "cut.stl: not an ASCII STL.*declares 8 triangles, which take 84 \+ 50 \* 8 = 484 bytes, but the \
file has 300" -- info "$T/cut.stl"

# Over the memory budget (4), at once.
expect subdivide_20_levels 4 "subdivided 20 times would have .* vertices" -- subdivide "$T/good.off" "$T/out.off" 20
expect plane_1e10 4 "generated plane would have 1e\+10 vertices" -- generate plane "$T/out.off" nx=100000 ny=100000
expect plane_over_budget 4 "over the memory budget of 1 MB" -- generate plane "$T/out.off" nx=400 ny=400 --memory-budget-mb 1
expect subdivide_over_budget 4 "over the memory budget of 1 MB" -- subdivide "$T/good.off" "$T/out.off" 6 --memory-budget-mb 1

# Work (0).
expect info 0 "vertices=6 faces=8.*topology: manifold" -- info "$T/good.off" --validate
expect info_non_manifold 0 "topology: 3 non-manifold edges" -- info "$T/fin.off"
expect repair_fin 0 "dropped 1 duplicate faces; split 2 vertices.*dropped face 9: duplicate of face 0.*split vertex 0 into" \
  -- repair "$T/fin.off" "$T/out.off"
"$BIN" info "$T/out.off" --validate >/dev/null 2>&1 || { echo "FAIL repaired mesh does not validate"; fails=$((fails + 1)); }
# The fin comes off the octahedron: the repair says so, with the components before and after (issue 28).
expect repair_detaches 0 "detached a piece of 1 faces from component 0 \(which keeps 8 faces\).*components: 1 before, 2 after \(detached pieces: 1\)" \
  -- repair "$T/fin.off" "$T/out.off"
expect repair_clean 0 "no change.*components: 1 before, 1 after" -- repair "$T/good.off" "$T/out.ply"
expect generate_plane 0 "wrote .*out.off \(121 vertices, 200 faces\); peak memory predicted 16.* MB, peak RSS" -- generate plane "$T/out.off" nx=10 ny=10
expect subdivide 0 "wrote .*out.obj \(18 vertices, 32 faces\)" -- subdivide "$T/good.off" "$T/out.obj" 1
# STL both ways: ASCII by default, binary 84 + 50 * 8 bytes; the octahedron's 24 corners weld back into its 6
# vertices, the same (checksum) from either encoding since its coordinates are floats.
"$BIN" convert "$T/good.off" "$T/good.stl"
head -n 1 "$T/good.stl" | grep -q '^solid good$' || { echo "FAIL convert_stl: not ASCII"; fails=$((fails + 1)); }
[ "$(stat -c %s "$T/good_bin.stl")" -eq 484 ] || { echo "FAIL convert_stl_binary: size"; fails=$((fails + 1)); }
expect info_stl_ascii 0 "name=good vertices=6 faces=8 checksum=.*topology: manifold" -- info "$T/good.stl" --validate
ascii_sum=$(grep -o 'checksum=[0-9a-f]*' "$T/message")
expect info_stl_binary 0 "name=good_bin vertices=6 faces=8 $ascii_sum topology: manifold" \
  -- info "$T/good_bin.stl" --validate
expect repair_stl 0 "no change.*wrote .*out.ply \(6 vertices, 8 faces\)" -- repair "$T/good_bin.stl" "$T/out.ply"
expect help 0 "repair" -- --help
expect subcommand_help 0 "--memory-budget-mb" -- generate --help

echo "meshtool_cli: $passes passed, $fails failed"
[ "$fails" -eq 0 ]
