#pragma once
//! A disk-like patch cut from a mesh by a vertex region: what coating transfer and transplanting map between
//! (Sorkine et al. 2004, section 5). The faces whose three corners lie in the region form the patch; it must be
//! one connected, manifold piece with exactly one boundary loop (Euler characteristic 1).
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

//! Cuts the patch of `region` (sorted or not, duplicates allowed) out of `mesh`. `what` names the patch in
//! messages ("source", "target"). \throw InputError naming the cause: an id out of range, a region with no whole
//! face, several components, a non-manifold edge or vertex, no boundary (closed) or several boundary loops
//! (holes, an annulus).
DiskPatch extract_disk_patch(const Mesh& mesh, const std::vector<int>& region, const std::string& what);

//! `region` without its ears: vertices in exactly one of the region's whole faces (a triangle sticking out of
//! the patch, whose boundary goes out to the tip and straight back), removed until none is left. A selection
//! by distance on a grid leaves such ears; a seam zippered along them folds. Sorted, without duplicates.
std::vector<int> trim_ears(const Mesh& mesh, const std::vector<int>& region);

}  // namespace db
