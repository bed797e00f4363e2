// Naive sparse build (the thesis' first version, section 2.4.1): A assembled from triplets, A^T formed
// explicitly, A^T A by a general sparse product. Kept as the reference the structured build is measured
// against, so it deliberately holds every intermediate the straightforward code holds, and keeps A^T for the
// frames' right-hand sides as that version did.
#include "systems/build_detail.h"

namespace db::detail {

NormalSystem build_naive(const EnergyOperator& op, const Unknowns& unk) {
  const int b = op.block();
  const Eigen::Index rows = static_cast<Eigen::Index>(b) * op.num_vertices();
  using Trip = Eigen::Triplet<double, int>;
  std::vector<Trip> tu, th;
  DenseMat target;
  walk_A(op, unk, target,
         [&](int row, int col, double v, bool unknown) { (unknown ? tu : th).emplace_back(row, col, v); });
  SpMat Au(rows, static_cast<Eigen::Index>(b) * unk.num_unknowns());
  SpMat Ah(rows, static_cast<Eigen::Index>(b) * unk.num_hard());
  Au.setFromTriplets(tu.begin(), tu.end());
  Ah.setFromTriplets(th.begin(), th.end());
  const std::size_t triplet_bytes = (tu.capacity() + th.capacity()) * sizeof(Trip);
  tu = {};
  th = {};
  SpMat At = Au.transpose();
  SpMat AtA = At * Au;
  const double w2 = unk.soft_weight * unk.soft_weight;
  for (int v : unk.soft_vertices)
    for (int c = 0; c < b; ++c) AtA.coeffRef(b * unk.unknown_of[v] + c, b * unk.unknown_of[v] + c) += w2;

  NormalSystem sys;
  sys.K = AtA.triangularView<Eigen::Upper>();
  sys.C = At * Ah;
  sys.g0 = At * target;
  sys.held_bytes = {{"triplets", triplet_bytes},
                    {"A", sparse_bytes(Au) + sparse_bytes(Ah)},
                    {"At", sparse_bytes(At)},
                    {"AtA", sparse_bytes(AtA)},
                    {"K_upper", sparse_bytes(sys.K)},
                    {"C", sparse_bytes(sys.C)},
                    {"b", static_cast<std::size_t>(target.size()) * sizeof(double)}};
  // A^T, A_h and b stay for the frames, as in the thesis' first version; A_u and A^T A go.
  sys.At.swap(At);
  sys.Ah.swap(Ah);
  sys.targets = std::move(target);
  return sys;
}

}  // namespace db::detail
