#pragma once
//! The multifrontal factor rounded to single precision, for the mixed-precision backend ("multifrontal_mixed"):
//! the same supernodes and FactorBlock layout as the double factor, half the bytes. Its solves read float
//! entries and compute in double (the factor is memory-bound to read; double arithmetic keeps M = L_f L_f^T an
//! exactly symmetric preconditioner up to double rounding). Why round a double factorization rather than factor
//! in float: the rounding errors of an elimination in float are of the order of float's epsilon times the
//! matrix's norm, far above the smallest eigenvalues of the ill-conditioned TF systems, while rounding each
//! entry of L perturbs it only relatively, and (L + E)(L + E)^T stays a close, positive definite preconditioner.
#include <cstddef>
#include <memory>

#include "solvers/multifrontal/symbolic.h"
#include "solvers/multifrontal/triangular_solve.h"

namespace db::multifrontal {

class FloatFactor {
 public:
  FloatFactor() = default;
  //! Rounds every supernode's block of F (in memory, or read back from its scratch file out of core).
  //! \throw BudgetError when the floats cannot be allocated.
  explicit FloatFactor(const FactorView& F);
  //! Bytes of the entries.
  std::size_t bytes() const { return entries_ * sizeof(float); }
  explicit operator bool() const { return values_ != nullptr; }
  //! y := (L L^T)^{-1} y with the rounded L, supernode by supernode (serial; y row-major, permuted order).
  void solve(const Symbolic& S, RowMajorMat& y) const;

 private:
  void forward(const Symbolic& S, int s, RowMajorMat& y, std::vector<double>& x) const;
  void backward(const Symbolic& S, int s, RowMajorMat& y, std::vector<double>& x) const;
  std::unique_ptr<float[]> values_;
  std::size_t entries_ = 0;
};

}  // namespace db::multifrontal
