#pragma once
//! Maps points of one patch's parameter disk into another's triangles: the correspondence of coating transfer
//! and transplanting (both patches on the unit disk, applications/disk_parameterization.h). A uniform grid over
//! the disk buckets the triangles; a point in no triangle (a boundary point on the circle lies just outside the
//! inscribed polygon of the other patch) takes the nearest triangle with its barycentric coordinates clamped.
#include <vector>

#include "applications/disk_parameterization.h"

namespace db {

struct BarycentricPoint {
  int face = -1;
  double w[3] = {0, 0, 0};  //!< non-negative, summing to 1
};

//! For each row of `query`: the face of (uv, F) containing it and its barycentric coordinates.
//! \throw InputError when F is empty or indexes outside uv.
std::vector<BarycentricPoint> locate_in_parameter_domain(const UV& uv, const Faces& F, const UV& query);

//! sum_c w_c values.row(F(face, c)) for each point: a per-vertex quantity carried along the map.
Points interpolate(const std::vector<BarycentricPoint>& at, const Faces& F, const Points& values);

}  // namespace db
