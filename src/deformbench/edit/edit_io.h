#pragma once
//! Reading edits: Botsch-Sorkine 2008 .sel/.def files, vertex index lists, and .edit case files that combine a mesh
//! with a selection and a handle transform.
#include <string>
#include <vector>

#include "solvers/base/types.h"
#include "edit/edit.h"
#include "mesh/mesh.h"

namespace db {

//! Botsch-Sorkine .sel: one status per line (0 fixed, 1 region of interest, 2 handle), `#` comments, blank lines
//! ignored. num_vertices < 0 skips the count check.
//! \throw InputError "<file>: line N: ..." for any other token, "<file>: selection has N entries but the mesh has M
//! vertices" for a count mismatch, or when the file cannot be read.
std::vector<Role> read_sel(const std::string& path, int num_vertices);

//! Botsch-Sorkine .def: the 4x4 handle transform, one row per line (row major), `#` comments. The matrix must be
//! finite and affine. \throw InputError naming the file and line.
Mat4 read_def(const std::string& path);

//! A drag's target positions (`targets = FILE` of a .edit file): three numbers per line (`x y z`, whitespace or
//! commas), `#` comments and blank lines ignored; one line per handle vertex in ascending vertex index, frame after
//! frame. \throw InputError naming the file and line for a line that is not three finite numbers, or a file without
//! any, or for more than max_rows lines (< 0: no bound; a .edit file's targets: kMaxFrames frames of its handle).
Points read_targets(const std::string& path, long long max_rows = -1);

//! .sel + .def as an Edit named after the .sel file stem. \throw InputError as read_sel / read_def.
Edit read_bs08_edit(const std::string& sel_path, const std::string& def_path, int num_vertices);

//! Vertex ids as picked in a modeller: integers separated by whitespace and/or commas, `#` comments.
//! \throw InputError naming the file and line for a non-integer or negative token, or an unreadable file, or one
//! larger than a list of a mesh with num_vertices vertices sensibly is (< 0: unknown).
std::vector<int> read_index_list(const std::string& path, int num_vertices = -1);

//! Edit from vertex lists: ROI vertices are Free, handle vertices Handle (they must lie in the ROI), all others
//! Fixed. Duplicates are allowed. Does not check that a free vertex remains (validate_edit does).
//! \throw InputError for an index outside [0, num_vertices), an empty region of interest, an empty handle, or
//! handle vertices outside the region of interest (counted, the first named).
Edit edit_from_lists(int num_vertices, const std::vector<int>& roi, const std::vector<int>& handle, const Mat4& T);

//! A mesh with its edit, ready for a method.
struct EditCase {
  Mesh mesh;
  Edit edit;
  std::string mesh_path;  //!< the mesh file as opened (relative paths resolved against the .edit file)
};

//! Loads an edit case from either
//!  (a) a path stem such that stem.off (or .ply / .obj), stem.sel and stem.def exist (Botsch-Sorkine layout), or
//!  (b) a `.edit` file of `key = value` lines (`#` comments). Keys (paths relative to the .edit file):
//!      mesh = PATH                      (required)
//!      name = TEXT                      (default: the .edit file stem)
//!      sel = PATH                       (BS08 statuses)  or  roi = SELECTION  plus  handle = SELECTION
//!      def = PATH  or  transform = SPEC (parse_transform)  or  targets = PATH (read_targets: a per-vertex drag,
//!      Edit::targets); exactly one of the three
//!    SELECTION is one of  all | sphere:cx,cy,cz,r | box:x0,y0,z0,x1,y1,z1 | kring:v,k | indices:FILE |
//!    nearest:x,y,z,count  (see select_by_spec).
//! Reads the mesh, validates mesh (non-manifold meshes load: see Manifold) and edit, and names the edit (the stem's
//! or the .edit's base name by default).
//! \throw InputError naming the file for every problem; a roi or handle selection that selects no vertex is named
//! with the mesh's extent.
EditCase load_edit_case(const std::string& spec);

//! The files load_edit_case(spec) reads, without reading any of them but a .edit file itself: the stem's mesh
//! (STEM.off when none exists yet), .sel and .def; or the .edit file, its mesh, sel, def, `indices:` selection
//! files, `def:` transform file and targets file. For refusing an output path that would overwrite an input
//! before any work.
//! \throw InputError as load_edit_case for an unreadable or malformed .edit file.
std::vector<std::string> edit_case_files(const std::string& spec);

}  // namespace db
