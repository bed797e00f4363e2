#pragma once
//! The matrix entries a run of consecutive supernodes assembles, as columns of the lower triangle, copied out of
//! the caller's upper triangle into a buffer each thread reuses.
//!
//! Why: a supernode's entries A(i, j), j its column, i >= j, lie in the upper triangle's columns i, one per row i
//! of its front. Read per front, every front row costs a visit (and a search) of one scattered column of A,
//! most of which hold no entry for that front: the small fronts' matrix pass took longer than their dense
//! kernels. A whole transposed copy reads A once but is new memory as large as A, whose first touch cost as much
//! (results/records/2026-11-24-tf-init-levers/). Here the rows a run of fronts needs are visited once per run, and the buffer is faulted
//! once per thread.
#include <vector>

#include "solvers/base/types.h"
#include "solvers/multifrontal/symbolic.h"

namespace db::multifrontal {

class MatrixChunk {
 public:
  //! The entries of each column of the lower triangle of `upper` (with sorted columns; its entries below the
  //! diagonal are not part of it), one pass over its row indices.
  static std::vector<int> lower_counts(const SpMat& upper);
  //! The lower-triangle columns of supernodes s0 .. s1 (consecutive) of P A P^T, given its upper triangle
  //! `upper` and lower_counts(upper).
  void load(const SpMat& upper, const std::vector<int>& counts, const Symbolic& S, int s0, int s1);
  //! Column j (one of the loaded supernodes'): its rows i >= j ascending, its values.
  const int* rows(int j) const { return row_.data() + ptr_[std::size_t(j - c0_)]; }
  const double* values(int j) const { return val_.data() + ptr_[std::size_t(j - c0_)]; }
  int count(int j) const { return ptr_[std::size_t(j - c0_) + 1] - ptr_[std::size_t(j - c0_)]; }
  //! The last supernode of the run starting at s0 that load() should take: consecutive supernodes up to `last`
  //! while their columns stay within a bound (at least s0 itself).
  static int run_end(const Symbolic& S, int s0, int last);

 private:
  int c0_ = 0;
  std::vector<int> ptr_, row_, outside_, mark_, cursor_;
  std::vector<double> val_;
  int stamp_ = 0;
};

}  // namespace db::multifrontal
