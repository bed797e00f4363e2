#pragma once
//! Per-vertex frames [t1 t2 n] of a parameterized patch: n the area-weighted vertex normal, t1 the direction the
//! parameter's u axis takes on the surface (the 1-ring's least-squares Jacobian d p / d uv applied to (1, 0),
//! projected into the tangent plane), t2 = n x t1. Two patches mapped onto one parameter disk get frames that
//! agree through the map, so detail written in one patch's frames reads correctly in the other's (coating
//! transfer; Sorkine et al. 2004 use the smooth surface's normal and a parameter-aligned tangent the same way).
#include <vector>

#include "applications/disk_parameterization.h"
#include "mesh/mesh.h"

namespace db {

//! One orthonormal, right-handed frame per vertex of `mesh` (columns t1, t2, n).
//! \throw InputError for a vertex whose normal vanishes (operators/frames.h vertex_normals).
std::vector<Mat3> tangent_frames(const Mesh& mesh, const Adjacency& adj, const UV& uv);

}  // namespace db
