#pragma once
//! Sparse least squares min ||A X - B|| by QR of A itself (SuiteSparseQR), not of the normal
//! equations A^T A: the condition number is not squared. Separate from LinearSolver because the
//! input is the rectangular A, not a symmetric system.
#include <memory>
#include <string>

#include "solvers/base/types.h"
#include "solvers/linear_solver.h"

namespace db {

class SpqrLeastSquares {
 public:
  //! `ordering`: "default" (SPQR's: COLAMD, METIS for large fill), "colamd", "amd", "metis", "natural".
  //! \throw Error for another value.
  explicit SpqrLeastSquares(const std::string& ordering = "default");
  ~SpqrLeastSquares();
  SpqrLeastSquares(const SpqrLeastSquares&) = delete;
  SpqrLeastSquares& operator=(const SpqrLeastSquares&) = delete;

  //! QR of A (full storage, m x n with m >= n).
  //! \throw SolverError on non-finite entries, m < n, or rank deficiency (rank estimate < n).
  void factorize(const SpMat& A);
  //! X (n x k) minimizing ||A X - B|| column by column; B is m x k. \throw SolverError before factorize.
  void solve(const DenseMat& B, DenseMat& X);
  //! n = columns of A; nnz_matrix = nnz(A); nnz_factor = nnz(R) (SPQR's bound); flops = SPQR's count;
  //! factor_bytes = memory CHOLMOD/SPQR hold for the factorization (R and the Householder vectors).
  FactorStats stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace db
