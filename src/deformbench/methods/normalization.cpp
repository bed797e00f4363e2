#include "methods/normalization.h"

#include "mesh/mesh.h"

namespace db {

Normalization Normalization::fit(const Points& V) {
  Normalization n;
  if (V.rows() == 0) return n;
  const Eigen::RowVector3d lo = V.colwise().minCoeff(), hi = V.colwise().maxCoeff();
  n.center = (0.5 * (lo + hi)).transpose();
  const double d = (hi - lo).norm();
  n.scale = d > 0 ? 1.0 / d : 1.0;
  return n;
}

Points Normalization::apply(const Points& V) const {
  return ((V.rowwise() - center.transpose()) * scale).eval();
}

Points Normalization::restore(const Points& Vn) const {
  return ((Vn / scale).rowwise() + center.transpose()).eval();
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
