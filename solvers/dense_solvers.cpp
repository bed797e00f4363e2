//! Dense backends on the expanded full matrix (reference / small-system baselines):
//! "dense_llt" (Eigen LLT), "lapack_potrf" (LAPACK dpotrf), "dense_ldlt_bk" (LAPACK dsytrf Bunch-Kaufman),
//! "dense_lu" (LAPACK dgetrf). lapack_potrf is the Cholesky of the same library and blocking as the other two, so
//! the dense Cholesky / LU / Bunch-Kaufman comparison is not one of Eigen's kernels against OpenBLAS'.
#include <limits>
#include <vector>

#include <Eigen/Cholesky>
#include <fmt/format.h>

#include "solvers/base/error.h"
#include "solvers/backends.h"
#include "solvers/blas_lapack.h"
#include "solvers/solver_util.h"

namespace db {
namespace {

using namespace solver_util;

//! Shared bookkeeping: budget check, pattern guard, dense expansion; subclasses factor and solve.
class DenseSolver : public LinearSolver {
 public:
  explicit DenseSolver(const SolverOptions& options) : singular_test_(options.pivot_singularity_test) {
    if (options.ordering != "default" && options.ordering != "natural")
      throw Error(fmt::format("dense backends take no fill-reducing ordering (got '{}'; valid: default, natural)",
                              options.ordering));
  }

  void analyze(const SpMat& upper_in) override {
    check_square(upper_in, name());
    check_dense_budget(Index(upper_in.rows()), name());
    SpMat storage;
    const SpMat& upper = compressed(upper_in, storage);
    guard_.remember(upper);
    set_stats(std::size_t(upper.rows()), std::size_t(upper.nonZeros()));
  }

  void factorize(const SpMat& upper_in) override {
    SpMat storage;
    const SpMat& upper = prepare_factorize(*this, guard_, upper_in, storage);
    factored_ = false;
    factor(dense_from_upper(upper), diagonal_of(upper));
    factored_ = true;
  }

  void factorize_dense(DenseMat& full) override {
    DenseMat A = std::move(full);
    full = DenseMat();
    if (A.rows() != A.cols())
      throw SolverError(fmt::format("{}: matrix is {} x {}, not square", name(), A.rows(), A.cols()));
    check_dense_budget(Index(A.rows()), name());
    if (!A.allFinite()) throw SolverError(fmt::format("{}: matrix holds a NaN or Inf", name()));
    guard_ = PatternGuard{};
    set_stats(std::size_t(A.rows()), std::size_t(A.rows() * (A.rows() + 1) / 2));
    factored_ = false;
    const DenseVec diag = A.diagonal();
    factor(std::move(A), diag);
    factored_ = true;
  }

  void solve(const DenseMat& B, DenseMat& X) override {
    if (!factored_) throw SolverError(fmt::format("{}: solve() before a successful factorize()", name()));
    check_rhs(B, Index(stats_.n), name());
    X = B;
    solve_in_place(X);
    check_finite_result(X, name());
  }

  FactorStats stats() const override { return stats_; }

 protected:
  virtual bool lu() const { return false; }
  virtual bool pivoted() const { return true; }
  //! Factors A (full symmetric); `diag` is its diagonal, for the pivot test.
  virtual void factor(DenseMat&& A, const DenseVec& diag) = 0;
  virtual void solve_in_place(DenseMat& X) = 0;

  //! LAPACK's 1-norm reciprocal condition estimate; below eps the matrix is singular to working
  //! precision (singular bi-Laplacians land well below it).
  void check_rcond(double rcond) const {
    if (!(rcond >= std::numeric_limits<double>::epsilon()))
      throw SolverError(fmt::format("{}: matrix numerically singular (rcond estimate {:.3g})", name(), rcond));
  }

  FactorStats stats_;
  const bool singular_test_;

 private:
  PatternGuard guard_;
  bool factored_ = false;

  void set_stats(std::size_t n_unknowns, std::size_t nnz_matrix) {
    factored_ = false;
    const double n = double(n_unknowns);
    stats_ = FactorStats{};
    stats_.n = n_unknowns;
    stats_.nnz_matrix = nnz_matrix;
    stats_.ordering_used = "none";
    stats_.nnz_factor = lu() ? std::size_t(n * n) : std::size_t(n * (n + 1) / 2);
    stats_.flops = lu() ? 2.0 * n * n * n / 3.0 : n * n * n / 3.0;
    stats_.factor_bytes = std::size_t(n * n) * sizeof(double) + (lu() || pivoted() ? std::size_t(n) * sizeof(int) : 0);
  }
};

class DenseLLT final : public DenseSolver {
 public:
  using DenseSolver::DenseSolver;
  std::string name() const override { return "dense_llt"; }

 protected:
  bool pivoted() const override { return false; }
  void factor(DenseMat&& A, const DenseVec& diag) override {
    llt_.compute(A);
    if (llt_.info() != Eigen::Success) throw SolverError("dense_llt: matrix not positive definite");
    const auto& L = llt_.matrixLLT();
    std::vector<double> pivots(static_cast<std::size_t>(L.rows()));
    for (Eigen::Index k = 0; k < L.rows(); ++k) pivots[std::size_t(k)] = L(k, k) * L(k, k);
    stats_.min_pivot_ratio = check_pivots(pivots, nullptr, diag, name(), singular_test_);
  }
  void solve_in_place(DenseMat& X) override { llt_.solveInPlace(X); }

 private:
  Eigen::LLT<DenseMat> llt_;
};

class LapackPotrf final : public DenseSolver {
 public:
  using DenseSolver::DenseSolver;
  std::string name() const override { return "lapack_potrf"; }

 protected:
  bool pivoted() const override { return false; }
  void factor(DenseMat&& A, const DenseVec& diag) override {
    const int n = int(A.rows());
    a_ = std::move(A);
    int info = 0;
    LAPACK_dpotrf("L", &n, a_.data(), &n, &info);
    if (info < 0) throw SolverError(fmt::format("lapack_potrf: dpotrf argument {} invalid", -info));
    if (info > 0) throw SolverError(fmt::format("lapack_potrf: not positive definite at column {}", info - 1));
    std::vector<double> pivots(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) pivots[std::size_t(k)] = a_(k, k) * a_(k, k);
    stats_.min_pivot_ratio = check_pivots(pivots, nullptr, diag, name(), singular_test_);
  }
  void solve_in_place(DenseMat& X) override {
    const int n = int(a_.rows()), nrhs = int(X.cols());
    int info = 0;
    LAPACK_dpotrs("L", &n, &nrhs, a_.data(), &n, X.data(), &n, &info);
    if (info != 0) throw SolverError(fmt::format("lapack_potrf: dpotrs failed (info {})", info));
  }

 private:
  DenseMat a_;
};

class DenseLdltBunchKaufman final : public DenseSolver {
 public:
  using DenseSolver::DenseSolver;
  std::string name() const override { return "dense_ldlt_bk"; }

 protected:
  void factor(DenseMat&& A, const DenseVec&) override {
    const int n = int(A.rows());
    const double anorm = n ? A.cwiseAbs().colwise().sum().maxCoeff() : 0.0;
    a_ = std::move(A);
    ipiv_.assign(std::size_t(n), 0);
    int info = 0, lwork = -1;
    double query = 0;
    LAPACK_dsytrf("L", &n, a_.data(), &n, ipiv_.data(), &query, &lwork, &info);
    lwork = std::max(1, int(query));
    std::vector<double> work(static_cast<std::size_t>(lwork));
    LAPACK_dsytrf("L", &n, a_.data(), &n, ipiv_.data(), work.data(), &lwork, &info);
    if (info < 0) throw SolverError(fmt::format("dense_ldlt_bk: dsytrf argument {} invalid", -info));
    if (info > 0)
      throw SolverError(fmt::format("dense_ldlt_bk: matrix singular (zero pivot D({0},{0}) of {1})", info - 1, n));
    double rcond = 0;
    std::vector<double> cwork(2 * std::size_t(n));
    std::vector<int> iwork(static_cast<std::size_t>(n));
    LAPACK_dsycon("L", &n, a_.data(), &n, ipiv_.data(), &anorm, &rcond, cwork.data(), iwork.data(), &info);
    check_rcond(rcond);
  }
  void solve_in_place(DenseMat& X) override {
    const int n = int(a_.rows()), nrhs = int(X.cols());
    int info = 0;
    LAPACK_dsytrs("L", &n, &nrhs, a_.data(), &n, ipiv_.data(), X.data(), &n, &info);
    if (info != 0) throw SolverError(fmt::format("dense_ldlt_bk: dsytrs failed (info {})", info));
  }

 private:
  DenseMat a_;
  std::vector<int> ipiv_;
};

class DenseLU final : public DenseSolver {
 public:
  using DenseSolver::DenseSolver;
  std::string name() const override { return "dense_lu"; }

 protected:
  bool lu() const override { return true; }
  void factor(DenseMat&& A, const DenseVec&) override {
    const int n = int(A.rows());
    const double anorm = n ? A.cwiseAbs().colwise().sum().maxCoeff() : 0.0;
    a_ = std::move(A);
    ipiv_.assign(std::size_t(n), 0);
    int info = 0;
    LAPACK_dgetrf(&n, &n, a_.data(), &n, ipiv_.data(), &info);
    if (info < 0) throw SolverError(fmt::format("dense_lu: dgetrf argument {} invalid", -info));
    if (info > 0) throw SolverError(fmt::format("dense_lu: matrix singular (U({0},{0}) = 0 of {1})", info - 1, n));
    double rcond = 0;
    std::vector<double> cwork(4 * std::size_t(n));
    std::vector<int> iwork(static_cast<std::size_t>(n));
    LAPACK_dgecon("1", &n, a_.data(), &n, &anorm, &rcond, cwork.data(), iwork.data(), &info);
    check_rcond(rcond);
  }
  void solve_in_place(DenseMat& X) override {
    const int n = int(a_.rows()), nrhs = int(X.cols());
    int info = 0;
    LAPACK_dgetrs("N", &n, &nrhs, a_.data(), &n, ipiv_.data(), X.data(), &n, &info);
    if (info != 0) throw SolverError(fmt::format("dense_lu: dgetrs failed (info {})", info));
  }

 private:
  DenseMat a_;
  std::vector<int> ipiv_;
};

}  // namespace

std::unique_ptr<LinearSolver> backends::make_dense(const std::string& kind, const SolverOptions& options) {
  if (kind == "llt") return std::make_unique<DenseLLT>(options);
  if (kind == "potrf") return std::make_unique<LapackPotrf>(options);
  if (kind == "ldlt_bk") return std::make_unique<DenseLdltBunchKaufman>(options);
  if (kind == "lu") return std::make_unique<DenseLU>(options);
  throw Error(fmt::format("unknown dense backend kind '{}'", kind));
}

}  // namespace db
