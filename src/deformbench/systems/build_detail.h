#pragma once
// Internal to systems/: the pieces every build shares, so the three builds differ only in what they store.
#include <vector>

#include "systems/normal_system.h"

namespace db::detail {

//! A row block matters only when it touches an unknown; rows of hard vertices alone are constant.
inline bool row_active(const std::vector<int>& cols, const Unknowns& unk) {
  for (int k : cols)
    if (unk.unknown_of[k] >= 0) return true;
  return false;
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

//! `pattern`: interaction_pattern(adj, unk) when the caller has it already; `threads`: 0 = worker_threads().
NormalSystem build_structured(const EnergyOperator& op, const Unknowns& unk, const InteractionPattern* pattern = nullptr,
                              int threads = 0);
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

}  // namespace db::detail
