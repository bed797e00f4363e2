#include "systems/least_squares_system.h"

#include <vector>

namespace db {

LeastSquaresSystem least_squares_system(const NormalSystem& sys, const Unknowns& unk, const DenseMat& xh,
                                        const DenseMat& u) {
  const int b = sys.block, rows_a = int(sys.At.cols()), soft = int(unk.soft_vertices.size());
  const double w = unk.soft_weight;
  std::vector<Eigen::Triplet<double, int>> t;
  t.reserve(std::size_t(sys.At.nonZeros()) + std::size_t(b * soft));
  for (int k = 0; k < sys.At.outerSize(); ++k)  // A_u = At^T
    for (SpMat::InnerIterator it(sys.At, k); it; ++it) t.emplace_back(int(it.col()), int(it.row()), it.value());
  LeastSquaresSystem ls;
  ls.b.setZero(rows_a + b * soft, sys.rhs_cols);
  ls.b.topRows(rows_a) = sys.targets;
  if (xh.rows() > 0) ls.b.topRows(rows_a) -= sys.Ah * xh;
  for (int k = 0; k < soft; ++k) {
    const int x = unk.unknown_of[unk.soft_vertices[k]];
    for (int c = 0; c < b; ++c) t.emplace_back(rows_a + b * k + c, b * x + c, w);
    ls.b.middleRows(rows_a + b * k, b) = w * u.middleRows(b * k, b);
  }
  ls.A.resize(rows_a + b * soft, sys.At.rows());
  ls.A.setFromTriplets(t.begin(), t.end());
  return ls;
}

}  // namespace db
