#pragma once
//! The edit of thesis Table 2-1, built the same way for every tier so that only the mesh size changes:
//!  - region of interest = the whole mesh (thesis section 2.1): every vertex is an unknown;
//!  - handle = the `handle_count` vertices nearest to the extreme vertex along the longest bounding-box axis
//!    (select_nearest around it, the thesis' example of a picked handle);
//!  - anchors = the `anchor_count` vertices nearest to the opposite extreme vertex, kept in place;
//!  - transform = a translation of `drag_fraction` x the bounding-box diagonal along the second-longest axis
//!    (a sideways drag of the tip; the frames of the drag interpolate it).
//! With soft constraints (thesis eq. 2-4) handle and anchors stay unknowns with weighted rows, so the system is
//! #V x #V (LAP) or 3#V x 3#V (TF), the sizes of the thesis' table.
#include <string>

#include "edit/edit.h"
#include "mesh/mesh.h"

namespace db::harness {

struct ThesisEditOptions {
  int handle_count = 100;
  int anchor_count = 100;
  double drag_fraction = 0.2;  //!< translation length / bounding-box diagonal
};

//! The edit described above. Anchors that would coincide with handle vertices (tiny meshes) are dropped.
//! \throw InputError when the mesh has fewer than 3 vertices, a count is < 1, or no anchor remains.
Edit make_thesis_edit(const Mesh& mesh, const ThesisEditOptions& opt = {});

//! One line for reports: "handle 100 v at +x extreme, 100 anchors at -x, translate 0.2 diag along y".
std::string describe_thesis_edit(const Mesh& mesh, const ThesisEditOptions& opt = {});

}  // namespace db::harness
