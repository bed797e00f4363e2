#pragma once
//! A disk-like patch cut from a mesh by a vertex region: what coating transfer and transplanting map between
//! (Sorkine et al. 2004, section 5). The faces whose three corners lie in the region form the patch; it must be
//! one connected, manifold piece with exactly one boundary loop (Euler characteristic 1) and a vertex inside it.
#include <string>
#include <vector>

#include "mesh/mesh.h"

namespace db {

struct DiskPatch {
  Mesh mesh;                  //!< the patch's vertices and faces, numbered locally
  std::vector<int> parent;    //!< local vertex -> vertex of the mesh it was cut from
  std::vector<int> boundary;  //!< the boundary loop (local ids) in face orientation, from the vertex of lowest parent id
  std::vector<char> on_boundary;  //!< per local vertex

  int num_vertices() const { return mesh.num_vertices(); }
};

//! What to do with the region's ears: vertices in exactly one of the region's whole faces (a triangle sticking out
//! of the patch, whose boundary goes out to the tip and straight back). A selection by distance on a grid leaves
//! such ears; a seam zippered along them folds. Trim removes them until none is left.
enum class Ears { Keep, Trim };

//! Cuts the patch of `region` (sorted or not, duplicates allowed) out of `mesh`, its ears trimmed first for
//! Ears::Trim. `what` names the patch in messages ("source", "target"). \throw InputError naming the cause: an id
//! out of range, a region with no whole face (with how many vertices it selects), several components, a
//! non-manifold edge or vertex, no boundary (closed) or several boundary loops (holes, an annulus), no interior
//! vertex (every vertex on the boundary: nothing for the applications' LSE solves to move).
DiskPatch extract_disk_patch(const Mesh& mesh, const std::vector<int>& region, const std::string& what,
                             Ears ears = Ears::Keep);

}  // namespace db
