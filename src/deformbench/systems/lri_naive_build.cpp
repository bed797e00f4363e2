// Naive build of an LRI edge energy: A_u and A_h assembled from triplets (one row block per directed edge that
// touches an unknown), then A_u^T, A_u^T A_u and A_u^T A_h by general sparse products. The reference the
// structured build is checked and measured against, so it holds every intermediate until it is done.
#include "systems/build_detail.h"

namespace db::detail {
namespace {

using Trip = Eigen::Triplet<double, int>;

// A_u and A_h as triplets, row block after row block.
struct EdgeTriplets {
  std::vector<Trip> u, h;
  int rows = 0;
};

EdgeTriplets edge_triplets(const Adjacency& adj, const Unknowns& unk, const EdgeRows& rows) {
  const int b = rows.block;
  EdgeTriplets A;
  for_each_edge_block(adj, unk, rows, true, [&](int i, int j, int, const double* P, const double* Q) {
    const int ui = unk.unknown_of[i], uj = unk.unknown_of[j], row = A.rows;
    for (int r = 0; r < b; ++r)
      for (int c = 0; c < b; ++c) {
        if (ui >= 0) A.u.emplace_back(row + r, b * ui + c, P[r * b + c]);
        else A.h.emplace_back(row + r, b * unk.hard_of[i] + c, P[r * b + c]);
        if (uj >= 0) A.u.emplace_back(row + r, b * uj + c, Q[r * b + c]);
        else A.h.emplace_back(row + r, b * unk.hard_of[j] + c, Q[r * b + c]);
      }
    A.rows += b;
  });
  return A;
}

}  // namespace

NormalSystem build_edge_naive(const Adjacency& adj, const Unknowns& unk, const EdgeRows& rows) {
  const int b = rows.block;
  const EdgeTriplets A = edge_triplets(adj, unk, rows);
  SpMat Au(A.rows, static_cast<Eigen::Index>(b) * unk.num_unknowns());
  SpMat Ah(A.rows, static_cast<Eigen::Index>(b) * unk.num_hard());
  Au.setFromTriplets(A.u.begin(), A.u.end());
  Ah.setFromTriplets(A.h.begin(), A.h.end());
  const SpMat At = Au.transpose();
  SpMat Kfull = (At * Au).pruned();
  const double w2 = unk.soft_weight * unk.soft_weight;
  for (int v : unk.soft_vertices)
    for (int c = 0; c < b; ++c) Kfull.coeffRef(b * unk.unknown_of[v] + c, b * unk.unknown_of[v] + c) += w2;
  NormalSystem sys;
  sys.K = Kfull.triangularView<Eigen::Upper>();
  sys.K.makeCompressed();
  sys.C = At * Ah;
  sys.held_bytes = {{"triplets", (A.u.size() + A.h.size()) * sizeof(Trip)},
                    {"A_u", sparse_bytes(Au)},
                    {"A_h", sparse_bytes(Ah)},
                    {"A_u^T", sparse_bytes(At)},
                    {"K_full", sparse_bytes(Kfull)},
                    {"K_upper", sparse_bytes(sys.K)},
                    {"C", sparse_bytes(sys.C)}};
  return sys;
}

}  // namespace db::detail
