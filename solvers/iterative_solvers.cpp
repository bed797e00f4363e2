//! Preconditioned conjugate gradients: "cg_jacobi" (diagonal) and "cg_ichol" (incomplete Cholesky).
#include <algorithm>

#include <Eigen/IterativeLinearSolvers>
#include <fmt/format.h>

#include "solvers/base/error.h"
#include "solvers/backends.h"
#include "solvers/solver_util.h"

namespace db {
namespace {

using namespace solver_util;

//! CG on the full matrix with Lower|Upper (Eigen then runs the product on both triangles, in parallel
//! where enabled). "factorize" computes the preconditioner; each solve starts from zero.
template <typename Preconditioner>
class CgSolver final : public LinearSolver {
  static constexpr bool kIchol = !std::is_same<Preconditioner, Eigen::DiagonalPreconditioner<double>>::value;

 public:
  explicit CgSolver(const SolverOptions& options) {
    // Jacobi has no ordering; Eigen's incomplete Cholesky is fixed to AMD here.
    const char* other = kIchol ? "amd" : "natural";
    if (options.ordering != "default" && options.ordering != other)
      throw Error(fmt::format("{}: unsupported ordering '{}' (valid: default, {})", name(), options.ordering, other));
    if (!(options.tolerance > 0) || options.max_iterations < 1)
      throw Error(fmt::format("{}: tolerance must be > 0 and max_iterations >= 1", name()));
    cg_.setTolerance(options.tolerance);
    cg_.setMaxIterations(options.max_iterations);
  }

  std::string name() const override { return kIchol ? "cg_ichol" : "cg_jacobi"; }

  void analyze(const SpMat& upper_in) override {
    check_square(upper_in, name());
    SpMat storage;
    const SpMat& upper = compressed(upper_in, storage);
    factored_ = false;
    full_from_upper(upper).swap(full_);
    cg_.analyzePattern(full_);
    guard_.remember(upper);
    stats_ = FactorStats{};
    stats_.n = std::size_t(upper.rows());
    stats_.nnz_matrix = std::size_t(upper.nonZeros());
    stats_.ordering_used = kIchol ? "amd" : "none";
  }

  void factorize(const SpMat& upper_in) override {
    SpMat storage;
    const SpMat& upper = prepare_factorize(*this, guard_, upper_in, storage);
    factored_ = false;
    full_from_upper(upper).swap(full_);
    cg_.factorize(full_);  // (re)binds full_ and computes the preconditioner
    const std::size_t n = stats_.n;
    if constexpr (kIchol) {
      if (cg_.preconditioner().info() != Eigen::Success)
        throw SolverError(fmt::format("cg_ichol: incomplete Cholesky failed (matrix not positive definite even "
                                      "after diagonal shifts)"));
      const auto& L = cg_.preconditioner().matrixL();
      // Incomplete L (values, row indices, column pointers), scaling vector, P and Pinv.
      stats_.factor_bytes = std::size_t(L.nonZeros()) * (sizeof(double) + sizeof(int)) + (n + 1) * sizeof(int) +
                            n * sizeof(double) + 2 * n * sizeof(int);
    } else {
      stats_.factor_bytes = n * sizeof(double);  // inverse diagonal
    }
    factored_ = true;
  }

  void solve(const DenseMat& B, DenseMat& X) override {
    if (!factored_) throw SolverError(fmt::format("{}: solve() before a successful factorize()", name()));
    check_rhs(B, Index(stats_.n), name());
    X.resize(B.rows(), B.cols());
    int iterations = 0;
    double achieved = 0;
    // Column by column, so the reported iterations/tolerance are the worst over the columns.
    for (Eigen::Index c = 0; c < B.cols(); ++c) {
      X.col(c) = cg_.solve(B.col(c));
      iterations = std::max(iterations, int(cg_.iterations()));
      achieved = std::max(achieved, double(cg_.error()));
      if (cg_.info() != Eigen::Success)
        throw SolverError(fmt::format("{}: not converged in {} iterations (relative residual {:.3g} > {:.3g})",
                                      name(), cg_.iterations(), cg_.error(), cg_.tolerance()));
    }
    stats_.iterations = iterations;
    stats_.achieved_tolerance = achieved;
    check_finite_result(X, name());
  }

  FactorStats stats() const override { return stats_; }

 private:
  SpMat full_;  // referenced by cg_ between factorize and solve
  Eigen::ConjugateGradient<SpMat, Eigen::Lower | Eigen::Upper, Preconditioner> cg_;
  PatternGuard guard_;
  FactorStats stats_;
  bool factored_ = false;
};

}  // namespace

std::unique_ptr<LinearSolver> backends::make_cg(bool ichol, const SolverOptions& options) {
  if (ichol)
    return std::make_unique<CgSolver<Eigen::IncompleteCholesky<double, Eigen::Lower, Eigen::AMDOrdering<int>>>>(options);
  return std::make_unique<CgSolver<Eigen::DiagonalPreconditioner<double>>>(options);
}

}  // namespace db
