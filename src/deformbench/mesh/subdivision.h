#pragma once
//! Uniform Loop subdivision (OpenMesh), used to make the larger tiers of the scaling series.
#include "mesh/mesh.h"

namespace db {

//! Applies `levels` (>= 0) rounds of Loop subdivision. Original vertices keep their indices (smoothed positions)
//! and new edge vertices are appended, so one level gives #V + #E vertices and 4 #F faces. Boundaries use the
//! Loop boundary rules. Deterministic: the same input gives bit-identical output. Name "<name>_loop<levels>".
//! \throw InputError when the faces cannot form an oriented 2-manifold (OpenMesh rejects a face) or levels < 0.
Mesh loop_subdivide(const Mesh& m, int levels);

}  // namespace db
