#include "methods/normalization.h"

#include <cmath>

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "mesh/mesh.h"

namespace db {

Normalization Normalization::fit(const Points& V) {
  Normalization n;
  if (V.rows() == 0) return n;
  const Eigen::RowVector3d lo = V.colwise().minCoeff(), hi = V.colwise().maxCoeff();
  n.center = (0.5 * lo + 0.5 * hi).transpose();  // halves first: lo + hi may overflow
  const double d = checked_bbox_diagonal(V);
  n.scale = d > 0 ? 1.0 / d : 1.0;
  return n;
}

Points Normalization::apply(const Points& V) const {
  return ((V.rowwise() - center.transpose()) * scale).eval();
}

Points Normalization::restore(const Points& Vn) const {
  Points V = ((Vn / scale).rowwise() + center.transpose()).eval();
  if (V.allFinite()) return V;
  for (Eigen::Index v = 0; v < V.rows(); ++v)
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(V(v, c)) && std::isfinite(Vn(v, c)))
        throw InputError(fmt::format("deformed vertex {}: its {} coordinate ({:g} times the bounding-box diagonal "
                                     "from the center) is beyond the largest double; scale the mesh down",
                                     v, "xyz"[c], Vn(v, c)));
  return V;  // non-finite already before restoring: the deformers report that as a solver failure
}

Mat4 Normalization::conjugate(const Mat4& T) const {
  Mat4 S = Mat4::Identity();
  S.topLeftCorner<3, 3>() *= scale;
  S.topRightCorner<3, 1>() = -scale * center;
  Mat4 Si = Mat4::Identity();
  Si.topLeftCorner<3, 3>() /= scale;
  Si.topRightCorner<3, 1>() = center;
  return S * T * Si;
}

}  // namespace db
