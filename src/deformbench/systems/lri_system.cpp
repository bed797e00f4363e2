#include "systems/lri_system.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.h"

namespace db {
namespace {

// out(c1, c2) = sum_r X(r, c1) Y(r, c2), b x b row-major.
inline void AtB(int b, const double* X, const double* Y, double* out) {
  for (int c1 = 0; c1 < b; ++c1)
    for (int c2 = 0; c2 < b; ++c2) {
      double s = 0;
      for (int r = 0; r < b; ++r) s += X[r * b + c1] * Y[r * b + c2];
      out[c1 * b + c2] = s;
    }
}

struct Counts {
  std::size_t rows = 0;          // active directed edges
  std::size_t nnz_Au = 0, nnz_Ah = 0;
  std::size_t blocks_K_upper = 0, blocks_K_full = 0, blocks_C = 0;
};

Counts count(const Adjacency& adj, const Unknowns& unk, int b) {
  Counts c;
  const std::size_t b2 = static_cast<std::size_t>(b) * b;
  std::vector<int> hard_mark(adj.num_vertices(), -1);
  for (int i = 0; i < adj.num_vertices(); ++i) {
    const bool ui = unk.unknown_of[i] >= 0;
    if (ui) {
      ++c.blocks_K_upper;
      ++c.blocks_K_full;
    }
    for (const int* p = adj.begin(i); p != adj.end(i); ++p) {
      const bool uj = unk.unknown_of[*p] >= 0;
      if (!ui && !uj) continue;
      ++c.rows;
      c.nnz_Au += b2 * (ui + uj);
      c.nnz_Ah += b2 * (!ui + !uj);
      if (ui && uj) {
        ++c.blocks_K_full;
        if (unk.unknown_of[*p] < unk.unknown_of[i]) ++c.blocks_K_upper;
      }
      if (ui && !uj) ++c.blocks_C;  // each unknown-hard pair once (from the unknown's side)
    }
  }
  return c;
}

void check_blocks_finite(int b, const double* P, const double* Q, int i, int j) {
  for (int k = 0; k < b * b; ++k)
    if (!std::isfinite(P[k]) || !std::isfinite(Q[k]))
      throw InputError(fmt::format("LRI: non-finite coefficient on edge ({}, {})", i, j));
}

}  // namespace

std::size_t predict_edge_system_bytes(const Adjacency& adj, const Unknowns& unk, int block, Build build) {
  const Counts c = count(adj, unk, block);
  const std::size_t b2 = static_cast<std::size_t>(block) * block, e = sizeof(double) + sizeof(int);
  const std::size_t nu = static_cast<std::size_t>(unk.num_unknowns());
  // Off-diagonal blocks are stored whole, the diagonal blocks as their upper triangles.
  const std::size_t K_upper = (c.blocks_K_upper - nu) * b2 + nu * block * (block + 1) / 2;
  const std::size_t C = c.blocks_C * b2;
  if (build == Build::Naive) {
    const std::size_t trip = (c.nnz_Au + c.nnz_Ah) * (2 * sizeof(int) + sizeof(double));
    return trip + (c.nnz_Au + c.nnz_Ah) * e + c.nnz_Au * e + c.blocks_K_full * b2 * e + K_upper * e + C * e;
  }
  return K_upper * e + C * e;
}

EdgeSystem build_edge_system(const Adjacency& adj, const Unknowns& unk, int block, const EdgeBlocks& blocks,
                             Build build, std::size_t byte_budget) {
  const int b = block, b2 = b * b, n = adj.num_vertices();
  if (build == Build::Dense) throw InputError("LRI: the dense build is not offered (use structured or naive)");
  if (static_cast<int>(unk.unknown_of.size()) != n)
    throw InputError("LRI: constraint classification does not match the mesh size");
  if (unk.num_unknowns() == 0) throw InputError("nothing to solve for: every vertex is hard-constrained");
  if (byte_budget > 0) {
    const std::size_t predicted = predict_edge_system_bytes(adj, unk, b, build);
    if (predicted > byte_budget)
      throw BudgetError(fmt::format("{} build of an LRI system (block {}) needs about {:.1f} MB, over the budget of "
                                    "{:.1f} MB",
                                    to_string(build), b, predicted / 1e6, byte_budget / 1e6));
  }
  EdgeSystem sys;
  sys.build = build;
  sys.block = b;
  const int nu = unk.num_unknowns(), nh = unk.num_hard();
  const double w2 = unk.soft_weight * unk.soft_weight;
  std::vector<double> P(b2), Q(b2), blk(b2);
  using Trip = Eigen::Triplet<double, int>;

  if (build == Build::Structured) {
    const InteractionPattern pat = interaction_pattern(adj, unk, 1);
    expand_upper(pat, b).swap(sys.K);  // not an assignment: Eigen 3.4 copies a returned SparseMatrix
    double* Kv = sys.K.valuePtr();
    const int* Kp = sys.K.outerIndexPtr();
    // Adds a b x b block X (row block ju, column block ku, ju <= ku) into the upper triangle.
    auto add_K = [&](int ju, int ku, const double* X) {
      const int t = pat.slot(ku, ju);
      for (int c2 = 0; c2 < b; ++c2) {
        const int base = Kp[b * ku + c2] + b * t;
        const int upto = ju == ku ? c2 + 1 : b;
        for (int c1 = 0; c1 < upto; ++c1) Kv[base + c1] += X[c1 * b + c2];
      }
    };
    std::vector<Trip> ctrip;
    ctrip.reserve(static_cast<std::size_t>(count(adj, unk, b).blocks_C) * 2 * b2);
    for (int i = 0; i < n; ++i) {
      const int ui = unk.unknown_of[i];
      for (int s = adj.off[i]; s < adj.off[i + 1]; ++s) {
        const int j = adj.nbr[s], uj = unk.unknown_of[j];
        if (ui < 0 && uj < 0) continue;
        blocks(i, j, s, P.data(), Q.data());
        check_blocks_finite(b, P.data(), Q.data(), i, j);
        if (ui >= 0) {
          AtB(b, P.data(), P.data(), blk.data());
          add_K(ui, ui, blk.data());
        }
        if (uj >= 0) {
          AtB(b, Q.data(), Q.data(), blk.data());
          add_K(uj, uj, blk.data());
        }
        if (ui >= 0 && uj >= 0) {
          if (ui < uj) AtB(b, P.data(), Q.data(), blk.data()), add_K(ui, uj, blk.data());
          else AtB(b, Q.data(), P.data(), blk.data()), add_K(uj, ui, blk.data());
        } else if (ui >= 0) {
          AtB(b, P.data(), Q.data(), blk.data());
          const int hj = unk.hard_of[j];
          for (int c1 = 0; c1 < b; ++c1)
            for (int c2 = 0; c2 < b; ++c2) ctrip.emplace_back(b * ui + c1, b * hj + c2, blk[c1 * b + c2]);
        } else {
          AtB(b, Q.data(), P.data(), blk.data());
          const int hi = unk.hard_of[i];
          for (int c1 = 0; c1 < b; ++c1)
            for (int c2 = 0; c2 < b; ++c2) ctrip.emplace_back(b * uj + c1, b * hi + c2, blk[c1 * b + c2]);
        }
      }
    }
    std::vector<double> eye(b2, 0.0);
    for (int c = 0; c < b; ++c) eye[c * b + c] = w2;
    for (int v : unk.soft_vertices) add_K(unk.unknown_of[v], unk.unknown_of[v], eye.data());
    sys.C.resize(static_cast<Eigen::Index>(b) * nu, static_cast<Eigen::Index>(b) * nh);
    const std::size_t trip_bytes = ctrip.size() * sizeof(Trip);
    sys.C.setFromTriplets(ctrip.begin(), ctrip.end());
    sys.held_bytes = {{"K_upper", sparse_bytes(sys.K)}, {"C", sparse_bytes(sys.C)}, {"C_triplets", trip_bytes}};
    return sys;
  }

  // Naive: A_u and A_h explicitly (one row block per active directed edge), then products.
  std::vector<Trip> tu, th;
  int row = 0;
  for (int i = 0; i < n; ++i) {
    const int ui = unk.unknown_of[i];
    for (int s = adj.off[i]; s < adj.off[i + 1]; ++s) {
      const int j = adj.nbr[s], uj = unk.unknown_of[j];
      if (ui < 0 && uj < 0) continue;
      blocks(i, j, s, P.data(), Q.data());
      check_blocks_finite(b, P.data(), Q.data(), i, j);
      for (int r = 0; r < b; ++r)
        for (int c = 0; c < b; ++c) {
          if (ui >= 0) tu.emplace_back(row + r, b * ui + c, P[r * b + c]);
          else th.emplace_back(row + r, b * unk.hard_of[i] + c, P[r * b + c]);
          if (uj >= 0) tu.emplace_back(row + r, b * uj + c, Q[r * b + c]);
          else th.emplace_back(row + r, b * unk.hard_of[j] + c, Q[r * b + c]);
        }
      row += b;
    }
  }
  SpMat Au(row, static_cast<Eigen::Index>(b) * nu), Ah(row, static_cast<Eigen::Index>(b) * nh);
  Au.setFromTriplets(tu.begin(), tu.end());
  Ah.setFromTriplets(th.begin(), th.end());
  const SpMat At = Au.transpose();
  SpMat Kfull = (At * Au).pruned();
  for (int v : unk.soft_vertices)
    for (int c = 0; c < b; ++c) Kfull.coeffRef(b * unk.unknown_of[v] + c, b * unk.unknown_of[v] + c) += w2;
  sys.K = Kfull.triangularView<Eigen::Upper>();
  sys.K.makeCompressed();
  sys.C = At * Ah;
  sys.held_bytes = {{"triplets", (tu.size() + th.size()) * sizeof(Trip)},
                    {"A_u", sparse_bytes(Au)},
                    {"A_h", sparse_bytes(Ah)},
                    {"A_u^T", sparse_bytes(At)},
                    {"K_full", sparse_bytes(Kfull)},
                    {"K_upper", sparse_bytes(sys.K)},
                    {"C", sparse_bytes(sys.C)}};
  return sys;
}

void add_At_targets(const Adjacency& adj, const Unknowns& unk, int block, const EdgeBlocks& blocks, const DenseMat& t,
                    DenseMat& g) {
  const int b = block, b2 = b * b, cols = static_cast<int>(t.cols());
  std::vector<double> P(b2), Q(b2);
  for (int i = 0; i < adj.num_vertices(); ++i) {
    const int ui = unk.unknown_of[i];
    for (int s = adj.off[i]; s < adj.off[i + 1]; ++s) {
      const int j = adj.nbr[s], uj = unk.unknown_of[j];
      if (ui < 0 && uj < 0) continue;
      blocks(i, j, s, P.data(), Q.data());
      for (int c = 0; c < cols; ++c)
        for (int r = 0; r < b; ++r) {
          const double tv = t(static_cast<Eigen::Index>(b) * s + r, c);
          if (tv == 0) continue;
          for (int k = 0; k < b; ++k) {
            if (ui >= 0) g(b * ui + k, c) += P[r * b + k] * tv;
            if (uj >= 0) g(b * uj + k, c) += Q[r * b + k] * tv;
          }
        }
    }
  }
}

}  // namespace db
