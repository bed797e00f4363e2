#pragma once
//! Handle-space precomputation (issue 16), the precompute / solve pair of a factored MinQuadWithFixed for edits
//! whose constraint values are affine in a few parameters theta (an affine handle map: 12; LAP's x, y, z share 4;
//! LRI's frames under a handle rotation share 3; a per-vertex drag of h handle vertices: 3h, LAP's x, y, z share h):
//!
//!   (x_h, u) = (x_h0, u0) + sum_k basis_k theta(k, c)   =>   x_u(:, c) = x_u0(:, c) + sum_k R(:, k) theta(k, c),
//!   [x_u0 | R] = K^-1 [rhs(x_h0, u0) | rhs_linear(basis)]      (one multi-right-hand-side solve).
//!
//! precompute lays the rest solution and the responses out per output row (rest values, then the m responses),
//! so a frame (evaluate) streams them once, on the worker threads, and writes the outputs: no right-hand side, no
//! solve. Output rows are named by `source`: a scalar unknown row of x_u, or a hard value row of x_h (whose
//! response is the basis itself), so the outputs can be every vertex in mesh order.
#include <cstddef>
#include <vector>

#include "solvers/base/types.h"
#include "systems/min_quad_with_fixed.h"

namespace db {

class HandleResponse {
 public:
  //! Output row i reads unknown row source[i] of x_u when source[i] >= 0, else hard value row -source[i] - 1.
  static int hard_row(int r) { return -r - 1; }

  //! xh0, soft0: the constraint values at theta = 0 (b#hard x cols, b#soft x cols, as MinQuadWithFixed::form_rhs
  //! takes them); xh_basis, soft_basis: one column per parameter (b#hard x m, b#soft x m), the same for every
  //! output column c. \throw SolverError from the solve, or for a non-finite response.
  void precompute(const MinQuadWithFixed& mq, const DenseMat& xh0, const DenseMat& soft0, const DenseMat& xh_basis,
                  const DenseMat& soft_basis, const std::vector<int>& source);
  //! Maps every output value y to y * scale + shift(coordinate): the deformers' normalization, folded into the
  //! stored rows so a frame writes restored positions. The coordinate of (row i, column c) is c with three
  //! columns, i % 3 with one (x, y, z interleaved).
  void scale_and_shift(double scale, const Vec3& shift);

  //! out[i * cols + c] = rest(i, c) + sum_k R(i, k) theta(k, c), for theta m x cols (row-major output: Points'
  //! layout). Returns false when some output is not finite (left for the caller to name).
  bool evaluate(const DenseMat& theta, double* out) const;

  int rows() const { return rows_; }
  int cols() const { return cols_; }
  int parameters() const { return m_; }
  //! Bytes one frame reads: the stored rows.
  std::size_t bytes() const { return data_.size() * sizeof(double); }
  double seconds() const { return seconds_; }  //!< of the last precompute (right-hand sides, solve, layout)
  bool empty() const { return rows_ == 0; }

 private:
  int rows_ = 0, cols_ = 0, m_ = 0;
  std::vector<double> data_;  // per row: cols rest values, then m responses
  double seconds_ = 0;
};

}  // namespace db
