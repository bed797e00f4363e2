#include "systems/lri_system.h"

#include <cmath>

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "core/timer.h"
#include "systems/build_detail.h"

namespace db {
namespace detail {

EdgeCounts count_edges(const Adjacency& adj, const Unknowns& unk, int b) {
  EdgeCounts c;
  const std::size_t b2 = static_cast<std::size_t>(b) * b;
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

}  // namespace detail

std::size_t predict_edge_system_bytes(const Adjacency& adj, const Unknowns& unk, int block, Build build) {
  const detail::EdgeCounts c = detail::count_edges(adj, unk, block);
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

NormalSystem build_edge_system(const Adjacency& adj, const Unknowns& unk, const EdgeRows& rows, Build build,
                               std::size_t byte_budget) {
  if (build == Build::Dense) throw InputError("LRI: the dense build is not offered (use structured or naive)");
  if (static_cast<int>(unk.unknown_of.size()) != adj.num_vertices())
    throw InputError("LRI: constraint classification does not match the mesh size");
  if (unk.num_unknowns() == 0) throw InputError("nothing to solve for: every vertex is hard-constrained");
  if (byte_budget > 0) {
    const std::size_t predicted = predict_edge_system_bytes(adj, unk, rows.block, build);
    if (predicted > byte_budget)
      throw BudgetError(fmt::format("{} build of an LRI system (block {}) needs about {:.1f} MB, over the budget of "
                                    "{:.1f} MB",
                                    to_string(build), rows.block, predicted / 1e6, byte_budget / 1e6));
  }
  Timer t;
  NormalSystem sys = build == Build::Naive ? detail::build_edge_naive(adj, unk, rows)
                                           : detail::build_edge_structured(adj, unk, rows);
  sys.build = build;
  sys.block = rows.block;
  sys.rhs_cols = 3;
  sys.build_seconds = t.seconds();
  return sys;
}

void add_At_targets(const Adjacency& adj, const Unknowns& unk, const EdgeRows& rows, const DenseMat& t, DenseMat& g) {
  const int b = rows.block, cols = static_cast<int>(t.cols());
  detail::for_each_edge_block(adj, unk, rows, false, [&](int i, int j, int s, const double* P, const double* Q) {
    const int ui = unk.unknown_of[i], uj = unk.unknown_of[j];
    for (int c = 0; c < cols; ++c)
      for (int r = 0; r < b; ++r) {
        const double tv = t(static_cast<Eigen::Index>(b) * s + r, c);
        if (tv == 0) continue;
        for (int k = 0; k < b; ++k) {
          if (ui >= 0) g(b * ui + k, c) += P[r * b + k] * tv;
          if (uj >= 0) g(b * uj + k, c) += Q[r * b + k] * tv;
        }
      }
  });
}

}  // namespace db
