// Dense build: A and A^T A as dense matrices, as in the thesis' "before" column (section 2.4.1 stored A
// densely). Only for small meshes; the caller checks predict_build_bytes against a budget first.
#include "systems/build_detail.h"

namespace db::detail {

NormalSystem build_dense(const EnergyOperator& op, const Unknowns& unk) {
  const int b = op.block();
  const Eigen::Index rows = static_cast<Eigen::Index>(b) * op.num_vertices();
  DenseMat Au = DenseMat::Zero(rows, static_cast<Eigen::Index>(b) * unk.num_unknowns());
  DenseMat Ah = DenseMat::Zero(rows, static_cast<Eigen::Index>(b) * unk.num_hard());
  DenseMat target;
  walk_A(op, unk, target, [&](int row, int col, double v, bool unknown) { (unknown ? Au : Ah)(row, col) = v; });
  NormalSystem sys;
  const Eigen::Index nu = Au.cols();
  sys.K_dense = DenseMat::Zero(nu, nu);
  sys.K_dense.selfadjointView<Eigen::Lower>().rankUpdate(Au.transpose());  // SYRK: A^T A
  sys.K_dense.triangularView<Eigen::StrictlyUpper>() = sys.K_dense.transpose();
  const double w2 = unk.soft_weight * unk.soft_weight;
  for (int v : unk.soft_vertices)
    for (int c = 0; c < b; ++c) sys.K_dense(b * unk.unknown_of[v] + c, b * unk.unknown_of[v] + c) += w2;
  sys.C_dense = Au.transpose() * Ah;
  sys.g0 = Au.transpose() * target;
  const auto bytes = [](const DenseMat& m) { return static_cast<std::size_t>(m.size()) * sizeof(double); };
  sys.held_bytes = {{"A", bytes(Au) + bytes(Ah)}, {"AtA", bytes(sys.K_dense)}, {"C", bytes(sys.C_dense)},
                    {"b", bytes(target)}};
  return sys;
}

}  // namespace db::detail
