#pragma once
// Internal to systems/: the pieces every build shares, so the three builds differ only in what they store.
#include <vector>

#include "operators/lri_rows.h"
#include "systems/normal_system.h"

namespace db::detail {

//! A row block matters only when it touches an unknown; rows of hard vertices alone are constant.
inline bool row_active(const std::vector<int>& cols, const Unknowns& unk) {
  for (int k : cols)
    if (unk.unknown_of[k] >= 0) return true;
  return false;
}

//! Walks A itself, for the builds that store it: each row block touching an unknown puts its target in
//! `target` (b n x r, zero elsewhere) and hands each of its coefficients to entry(row, col, value, unknown),
//! col counting the unknowns' columns where `unknown`, else the hard vertices'.
template <class Entry>
void walk_A(const EnergyOperator& op, const Unknowns& unk, DenseMat& target, Entry&& entry) {
  const int n = op.num_vertices(), b = op.block(), r = op.rhs_cols(), b2 = b * b;
  target = DenseMat::Zero(static_cast<Eigen::Index>(b) * n, r);
  std::vector<int> cols;
  std::vector<double> coeffs;
  double tgt[3];
  for (int i = 0; i < n; ++i) {
    op.row(i, cols, coeffs);
    if (!row_active(cols, unk)) continue;
    op.target(i, tgt);
    for (int rr = 0; rr < b; ++rr)
      for (int col = 0; col < r; ++col) target(b * i + rr, col) = tgt[rr * r + col];
    for (std::size_t a = 0; a < cols.size(); ++a) {
      const int ku = unk.unknown_of[cols[a]], k = ku >= 0 ? ku : unk.hard_of[cols[a]];
      for (int rr = 0; rr < b; ++rr)
        for (int c = 0; c < b; ++c) entry(b * i + rr, b * k + c, coeffs[b2 * a + rr * b + c], ku >= 0);
    }
  }
}

//! out(c1, c2) = sum_r X(r, c1) Y(r, c2) for B x B row-major blocks.
template <int B>
inline void block_AtB(const double* X, const double* Y, double* out) {
  for (int c1 = 0; c1 < B; ++c1)
    for (int c2 = 0; c2 < B; ++c2) {
      double s = 0;
      for (int r = 0; r < B; ++r) s += X[r * B + c1] * Y[r * B + c2];
      out[c1 * B + c2] = s;
    }
}

//! out(c1, c2) = sum_r X(r, c1) Y(r, c2) for b x b row-major blocks of a size known at run time only.
inline void block_AtB(int b, const double* X, const double* Y, double* out) {
  for (int c1 = 0; c1 < b; ++c1)
    for (int c2 = 0; c2 < b; ++c2) {
      double s = 0;
      for (int r = 0; r < b; ++r) s += X[r * b + c1] * Y[r * b + c2];
      out[c1 * b + c2] = s;
    }
}

//! `pattern`: interaction_pattern(adj, unk) when the caller has it already; `threads`: 0 = worker_threads().
//! [first, last) (last -1: all): the block columns of K, rows of C and g0 built (a rank share), the rest empty.
NormalSystem build_structured(const EnergyOperator& op, const Unknowns& unk, const InteractionPattern* pattern = nullptr,
                              int threads = 0, int first = 0, int last = -1);
NormalSystem build_naive(const EnergyOperator& op, const Unknowns& unk);
NormalSystem build_dense(const EnergyOperator& op, const Unknowns& unk);

//! Nonzeros of one row block stencil summed over active rows (scalar entries of A_u and A_h).
struct StencilCounts {
  std::size_t rows = 0;       // active row blocks
  std::size_t nnz_Au = 0, nnz_Ah = 0;
  std::size_t nnz_K_upper = 0, nnz_K_full = 0;  // scalar nonzeros of K
  std::size_t nnz_C = 0;
};
StencilCounts count_stencil(const EnergyOperator& op, const Unknowns& unk);

// LRI's edge energies (systems/lri_system.h).
NormalSystem build_edge_structured(const Adjacency& adj, const Unknowns& unk, const EdgeRows& rows);
NormalSystem build_edge_naive(const Adjacency& adj, const Unknowns& unk, const EdgeRows& rows);

//! Sizes of an edge energy's matrices, counted over the directed edges that touch an unknown.
struct EdgeCounts {
  std::size_t rows = 0;  // active directed edges
  std::size_t nnz_Au = 0, nnz_Ah = 0;
  std::size_t blocks_K_upper = 0, blocks_K_full = 0, blocks_C = 0;
};
EdgeCounts count_edges(const Adjacency& adj, const Unknowns& unk, int b);

//! \throw InputError naming the edge when P_ij or Q_ij holds a NaN or Inf.
void check_blocks_finite(int b, const double* P, const double* Q, int i, int j);

//! Calls f(i, j, slot, P, Q) for every directed edge (i, j) that touches an unknown (edges between hard vertices
//! do not enter the system), in the order of adj.nbr, with its blocks from `rows`, checked finite on request.
template <class F>
void for_each_edge_block(const Adjacency& adj, const Unknowns& unk, const EdgeRows& rows, bool check_finite, F&& f) {
  const int b = rows.block;
  std::vector<double> P(b * b), Q(b * b);
  for (int i = 0; i < adj.num_vertices(); ++i)
    for (int s = adj.off[i]; s < adj.off[i + 1]; ++s) {
      const int j = adj.nbr[s];
      if (unk.unknown_of[i] < 0 && unk.unknown_of[j] < 0) continue;
      rows.blocks(i, j, s, P.data(), Q.data());
      if (check_finite) check_blocks_finite(b, P.data(), Q.data(), i, j);
      f(i, j, s, P.data(), Q.data());
    }
}

}  // namespace db::detail
