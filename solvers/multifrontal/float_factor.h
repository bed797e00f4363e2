#pragma once
//! The multifrontal factor rounded to single precision, for the mixed-precision backend ("multifrontal_mixed"):
//! the same supernodes and FactorBlock layout as the double factor, half the bytes. Its solves are the double
//! factor's (triangular_solve.h: the same supernodes, threads and kernels) reading float entries and computing
//! in double: a solve streams half the bytes of a double one, and double arithmetic keeps M = L_f L_f^T an
//! exactly symmetric preconditioner up to double rounding. Why round a double factorization rather than factor
//! in float: the rounding errors of an elimination in float are of the order of float's epsilon times the
//! matrix's norm, far above the smallest eigenvalues of the ill-conditioned TF systems, while rounding each
//! entry of L perturbs it only relatively, and (L + E)(L + E)^T stays a close, positive definite preconditioner.
#include <cstddef>
#include <memory>
#include <vector>

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
  //! The factor as the solves read it (S: the structure it was rounded from).
  FloatFactorView view(const Symbolic& S) const { return {S, values_.get()}; }
  //! y := (L L^T)^{-1} y with the rounded L, split among threads by `plan` (y row-major, permuted order; acc:
  //! forward_all's per-thread scratch).
  void solve(const Symbolic& S, const Plan& plan, RowMajorMat& y, std::vector<RowMajorMat>& acc) const;

 private:
  std::unique_ptr<float[]> values_;
  std::size_t entries_ = 0;
};

}  // namespace db::multifrontal
