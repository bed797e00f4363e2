// Structured build of an LRI edge energy: K's upper triangle laid out from the 1-ring adjacency (a row block
// couples only the two ends of its edge) and filled edge by edge with P^T P, P^T Q and Q^T Q; C collected as
// triplets (the coupling to hard vertices is a thin band). A is never stored.
#include "systems/build_detail.h"

namespace db::detail {
namespace {

using Trip = Eigen::Triplet<double, int>;

// Adds b x b blocks into the upper triangle of K as expand_upper(pattern, b) laid it out.
class UpperBlocks {
 public:
  UpperBlocks(const InteractionPattern& pat, SpMat& K, int b)
      : pat_(pat), Kv_(K.valuePtr()), Kp_(K.outerIndexPtr()), b_(b) {}

  //! X: the block of row block ju and column block ku, ju <= ku.
  void add(int ju, int ku, const double* X) const {
    const int t = pat_.slot(ku, ju);
    for (int c2 = 0; c2 < b_; ++c2) {
      const int base = Kp_[b_ * ku + c2] + b_ * t;
      const int upto = ju == ku ? c2 + 1 : b_;
      for (int c1 = 0; c1 < upto; ++c1) Kv_[base + c1] += X[c1 * b_ + c2];
    }
  }

 private:
  const InteractionPattern& pat_;
  double* Kv_;
  const int* Kp_;
  int b_;
};

// C's block X between unknown u and hard vertex h, as triplets.
void add_C(int b, int u, int h, const double* X, std::vector<Trip>& ctrip) {
  for (int c1 = 0; c1 < b; ++c1)
    for (int c2 = 0; c2 < b; ++c2) ctrip.emplace_back(b * u + c1, b * h + c2, X[c1 * b + c2]);
}

// The normal-equation blocks of directed edge (i, j) with unknown indices ui, uj (-1: hard) and blocks P, Q.
void add_edge(const UpperBlocks& K, const Unknowns& unk, int b, int i, int j, const double* P, const double* Q,
              double* blk, std::vector<Trip>& ctrip) {
  const int ui = unk.unknown_of[i], uj = unk.unknown_of[j];
  if (ui >= 0) {
    block_AtB(b, P, P, blk);
    K.add(ui, ui, blk);
  }
  if (uj >= 0) {
    block_AtB(b, Q, Q, blk);
    K.add(uj, uj, blk);
  }
  if (ui >= 0 && uj >= 0) {
    if (ui < uj) block_AtB(b, P, Q, blk), K.add(ui, uj, blk);
    else block_AtB(b, Q, P, blk), K.add(uj, ui, blk);
  } else if (ui >= 0) {
    block_AtB(b, P, Q, blk);
    add_C(b, ui, unk.hard_of[j], blk, ctrip);
  } else {
    block_AtB(b, Q, P, blk);
    add_C(b, uj, unk.hard_of[i], blk, ctrip);
  }
}

}  // namespace

NormalSystem build_edge_structured(const Adjacency& adj, const Unknowns& unk, const EdgeRows& rows) {
  const int b = rows.block, b2 = b * b;
  NormalSystem sys;
  const InteractionPattern pat = interaction_pattern(adj, unk, 1);
  expand_upper(pat, b).swap(sys.K);  // not an assignment: Eigen 3.4 copies a returned SparseMatrix
  const UpperBlocks K(pat, sys.K, b);
  std::vector<Trip> ctrip;
  ctrip.reserve(static_cast<std::size_t>(count_edges(adj, unk, b).blocks_C) * 2 * b2);
  std::vector<double> blk(b2);
  for_each_edge_block(adj, unk, rows, true, [&](int i, int j, int, const double* P, const double* Q) {
    add_edge(K, unk, b, i, j, P, Q, blk.data(), ctrip);
  });
  const double w2 = unk.soft_weight * unk.soft_weight;
  std::vector<double> eye(b2, 0.0);
  for (int c = 0; c < b; ++c) eye[c * b + c] = w2;
  for (int v : unk.soft_vertices) K.add(unk.unknown_of[v], unk.unknown_of[v], eye.data());
  sys.C.resize(static_cast<Eigen::Index>(b) * unk.num_unknowns(), static_cast<Eigen::Index>(b) * unk.num_hard());
  const std::size_t trip_bytes = ctrip.size() * sizeof(Trip);
  sys.C.setFromTriplets(ctrip.begin(), ctrip.end());
  sys.held_bytes = {{"K_upper", sparse_bytes(sys.K)}, {"C", sparse_bytes(sys.C)}, {"C_triplets", trip_bytes}};
  return sys;
}

}  // namespace db::detail
