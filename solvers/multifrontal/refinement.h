#pragma once
//! The solve of the mixed-precision backend: iterative refinement of x with residuals b - A x accumulated in
//! twice double's precision (error-free transformations), each correction A d = r solved by conjugate gradients in double,
//! preconditioned by the single-precision factor (float_factor.h).
//! Why CG for the corrections and not the factor's solve alone (plain refinement, x += M^-1 r): on the TF systems
//! the rounded factor's own solve is far from A's (at 104k vertices it was off by most of the bounding-box
//! diagonal) and plain refinement converges slowly or stalls there, while CG needs of M only that it be
//! symmetric positive definite.
//! Why extended-precision residuals and a stopping rule on the correction, not on a double residual: these
//! systems are so ill-conditioned that a residual computed in double no longer measures the error of x (at 104k
//! TF, x moved by 5e-4 of the diagonal between two solves whose double residuals were both at rounding level),
//! so a double residual can only bring x to a double direct solve's backward error, whose forward error is of the
//! same order (double solves with other orderings or backends differ by as much). An accurate residual lets each
//! refinement step shrink the error of x itself, and the size of the last correction bounds what is left.
#include <functional>
#include <string>
#include <vector>

#include "solvers/base/types.h"
#include "solvers/multifrontal/triangular_solve.h"

namespace db::multifrontal {

//! Y := A X for the symmetric A given by its upper triangle (rows of X and Y: unknowns; columns: right-hand
//! sides).
void symmetric_product(const SpMat& upper, const RowMajorMat& X, RowMajorMat& Y);
//! R := B - A X, each entry accumulated in double-double (as if in twice double's precision) and rounded once.
void extended_residual(const SpMat& upper, const RowMajorMat& X, const RowMajorMat& B, RowMajorMat& R);
//! extended_residual() before its rounding: B - A X = R + low (low: R's layout, row-major), for callers that add
//! several such sums in double-double before rounding (the ranks' shares of A, mumps_ranks_solver.cpp).
void extended_residual_parts(const SpMat& upper, const RowMajorMat& X, const RowMajorMat& B, RowMajorMat& R,
                             std::vector<double>& low);

//! The system a refinement solves, by its two products: Y := A X in double, and R := B - A X in double-double
//! rounded once (extended_residual()). One process: from A's upper triangle; on ranks, collective ones.
struct RefinedSystem {
  std::function<void(const RowMajorMat& X, RowMajorMat& Y)> product;
  std::function<void(const RowMajorMat& X, const RowMajorMat& B, RowMajorMat& R)> residual;
};
//! The products of the upper triangle `upper` (kept by reference).
RefinedSystem refined_system(const SpMat& upper);

struct Refinement {
  int iterations = 0;        //!< CG iterations (products with A and preconditioner solves), all steps together
  int steps = 0;             //!< refinement steps (corrections added to x)
  double residual = 0;       //!< largest ||b - A x||_2 / ||b||_2 over the columns, at the end (double-double)
  double last_correction = 0;  //!< largest ||d||_inf / ||x||_inf of the last correction d over the columns
};

//! X := A^-1 B, every column of B at once, from X = M^-1 B: refinement steps until each column's last
//! correction is at most `tolerance` relative to it (max-norms). `precondition(Y)`: Y := M^-1 Y, M symmetric
//! positive definite.
//! \throw SolverError naming the tolerance and the correction reached when the CG iterations of all steps
//! exceed `max_iterations`, when a correction is no longer half the one before (stalled above the tolerance),
//! or when p^T A p <= 0 (A not positive definite); `who` (the backend) begins the message.
//! Deterministic: processes that call it with bitwise equal inputs and products take the same steps.
Refinement refine(const RefinedSystem& A, const std::function<void(RowMajorMat&)>& precondition,
                  const RowMajorMat& B, RowMajorMat& X, double tolerance, int max_iterations,
                  const std::string& who = "multifrontal_mixed");

}  // namespace db::multifrontal
