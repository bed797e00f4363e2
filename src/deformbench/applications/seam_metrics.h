#pragma once
//! Boundary continuity of a patch inside its mesh: the dihedral angles across the patch's boundary edges (the
//! angle between the normals of the face inside the patch and the face outside). A graft or a coating that
//! leaves a crease at the seam shows as a larger angle than the surface had there before.
#include "applications/disk_patch.h"
#include "mesh/mesh.h"

namespace db {

struct SeamAngles {
  double max_deg = 0, mean_deg = 0;
  int edges = 0;  //!< boundary edges with a face on both sides (0 when the patch is the whole mesh)
};

//! The angles across `patch`'s boundary loop in `mesh` (the mesh it was cut from, or one with its connectivity).
SeamAngles seam_angles(const Mesh& mesh, const DiskPatch& patch);

}  // namespace db
