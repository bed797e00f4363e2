#pragma once
//! Boundary continuity of a patch inside its mesh: the dihedral angles across the patch's boundary edges (the
//! angle between the normals of the two faces on either side). A graft or a coating that leaves a crease at the
//! seam shows as a larger angle than the surface had there before.
#include <utility>
#include <vector>

#include "applications/disk_patch.h"
#include "mesh/mesh.h"

namespace db {

struct SeamAngles {
  double max_deg = 0, mean_deg = 0;
  int edges = 0;  //!< edges with a face on both sides (0 when the patch is the whole mesh)
};

//! The angles across the given edges (vertex pairs of `mesh`, either order); edges without two faces are skipped.
SeamAngles dihedral_angles(const Mesh& mesh, const std::vector<std::pair<int, int>>& edges);

//! The angles across `patch`'s boundary loop in `mesh` (the mesh it was cut from, or one with its connectivity).
SeamAngles seam_angles(const Mesh& mesh, const DiskPatch& patch);

//! The angles across every edge of the faces [first_face, #F) of `mesh`: a band of faces, its two rims included.
SeamAngles band_angles(const Mesh& mesh, int first_face);

}  // namespace db
