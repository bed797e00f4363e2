//! Eigen's sparse direct backends: "eigen_simplicial_llt", "eigen_simplicial_ldlt" (upper triangle,
//! AMD or natural ordering) and "eigen_sparse_lu" (supernodal LU of the full matrix, COLAMD by default).
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <fmt/format.h>

#include "solvers/base/error.h"
#include "solvers/backends.h"
#include "solvers/solver_util.h"

namespace db {
namespace {

using namespace solver_util;

//! Bookkeeping shared by the Eigen backends: checks, pattern guard, stats, solve.
class EigenSparseBase : public LinearSolver {
 public:
  void analyze(const SpMat& upper_in) override {
    check_square(upper_in, name());
    SpMat storage;
    const SpMat& upper = compressed(upper_in, storage);
    factored_ = false;
    do_analyze(upper);
    guard_.remember(upper);
    stats_ = FactorStats{};
    stats_.n = std::size_t(upper.rows());
    stats_.nnz_matrix = std::size_t(upper.nonZeros());
    stats_.ordering_used = ordering_;
  }

  void factorize(const SpMat& upper_in) override {
    SpMat storage;
    const SpMat& upper = prepare_factorize(*this, guard_, upper_in, storage);
    factored_ = false;
    do_factorize(upper);
    factored_ = true;
  }

  void solve(const DenseMat& B, DenseMat& X) override {
    if (!factored_) throw SolverError(fmt::format("{}: solve() before a successful factorize()", name()));
    check_rhs(B, Index(stats_.n), name());
    do_solve(B, X);
    check_finite_result(X, name());
  }

  FactorStats stats() const override { return stats_; }

 protected:
  explicit EigenSparseBase(std::string ordering) : ordering_(std::move(ordering)) {}
  virtual void do_analyze(const SpMat& upper) = 0;
  virtual void do_factorize(const SpMat& upper) = 0;
  virtual void do_solve(const DenseMat& B, DenseMat& X) = 0;

  FactorStats stats_;

 private:
  std::string ordering_;
  PatternGuard guard_;
  bool factored_ = false;
};

//! SimplicialLLT / SimplicialLDLT reading the upper triangle; `Ordering` is AMD or natural.
template <template <typename, int, typename> class Simplicial, typename Ordering>
class EigenSimplicial final : public EigenSparseBase {
  using Solver = Simplicial<SpMat, Eigen::Upper, Ordering>;
  static constexpr bool kLDLT = std::is_same<Solver, Eigen::SimplicialLDLT<SpMat, Eigen::Upper, Ordering>>::value;

 public:
  explicit EigenSimplicial(std::string ordering) : EigenSparseBase(std::move(ordering)) {}
  std::string name() const override { return kLDLT ? "eigen_simplicial_ldlt" : "eigen_simplicial_llt"; }

 protected:
  void do_analyze(const SpMat& upper) override {
    solver_.analyzePattern(upper);
    if (solver_.info() != Eigen::Success) throw SolverError(fmt::format("{}: analyzePattern failed", name()));
  }

  void do_factorize(const SpMat& upper) override {
    solver_.factorize(upper);
    if (solver_.info() != Eigen::Success)
      throw SolverError(fmt::format("{}: matrix not positive definite (zero or negative pivot)", name()));
    // Stored L: LLT holds the diagonal first in each column; LDLT holds strictly-lower L plus D.
    const SpMat& L = solver_.matrixL().nestedExpression();
    const Index n = Index(L.cols());
    std::vector<double> pivots(static_cast<std::size_t>(n));
    for (Index k = 0; k < n; ++k) {
      if constexpr (kLDLT) {
        pivots[std::size_t(k)] = solver_.vectorD()(k);
      } else {
        const double l = L.valuePtr()[L.outerIndexPtr()[k]];
        pivots[std::size_t(k)] = l * l;
      }
    }
    // Eigen factors P A P^T; Pinv maps factor positions back to original indices (empty = identity).
    const auto& pinv = solver_.permutationPinv();
    stats_.min_pivot_ratio = check_pivots(pivots, pinv.size() ? pinv.indices().data() : nullptr, upper, name());

    // L's column pointers are exact (symbolic counts); LDLT stores the unit diagonal implicitly.
    const std::size_t lnz = std::size_t(L.nonZeros()) + (kLDLT ? std::size_t(n) : 0);
    stats_.nnz_factor = lnz;
    std::vector<int> counts(std::size_t(n) + 1, 0);
    for (Index k = 0; k < n; ++k)
      counts[std::size_t(k) + 1] = counts[std::size_t(k)] + (L.outerIndexPtr()[k + 1] - L.outerIndexPtr()[k]) +
                                   (kLDLT ? 1 : 0);
    stats_.flops = cholesky_flops(counts.data(), n);
    // L (values + row indices + column pointers), D for LDLT, P and Pinv, etree and column counts.
    stats_.factor_bytes = std::size_t(L.nonZeros()) * (sizeof(double) + sizeof(int)) + (std::size_t(n) + 1) * sizeof(int) +
                          (kLDLT ? std::size_t(n) * sizeof(double) : 0) + 4 * std::size_t(n) * sizeof(int);
  }

  void do_solve(const DenseMat& B, DenseMat& X) override { X = solver_.solve(B); }

 private:
  Solver solver_;
};

//! SparseLU of the full symmetric matrix (it has no symmetric mode).
template <typename Ordering>
class EigenSparseLU final : public EigenSparseBase {
 public:
  explicit EigenSparseLU(std::string ordering) : EigenSparseBase(std::move(ordering)) {}
  std::string name() const override { return "eigen_sparse_lu"; }

 protected:
  void do_analyze(const SpMat& upper) override {
    full_from_upper(upper).swap(full_);
    solver_.analyzePattern(full_);  // SparseLU sets info() only in factorize()
  }

  void do_factorize(const SpMat& upper) override {
    full_from_upper(upper).swap(full_);
    solver_.factorize(full_);
    if (solver_.info() != Eigen::Success)
      throw SolverError(fmt::format("{}: factorization failed: {}", name(), solver_.lastErrorMessage()));
    const std::size_t n = stats_.n;
    // nnzL counts the supernodal L blocks (with their diagonal blocks), nnzU the rest of U.
    stats_.nnz_factor = std::size_t(solver_.nnzL()) + std::size_t(solver_.nnzU());
    // Estimate: values + row indices of L and U, plus row/column permutations; Eigen's internal
    // workspaces (grown by its memory expansion) are not visible and not counted.
    stats_.factor_bytes = stats_.nnz_factor * (sizeof(double) + sizeof(int)) + 4 * n * sizeof(int);
    stats_.flops = 0;  // SparseLU does not report a flop count
  }

  void do_solve(const DenseMat& B, DenseMat& X) override {
    X = solver_.solve(B);
    if (solver_.info() != Eigen::Success) throw SolverError(fmt::format("{}: solve failed", name()));
  }

 private:
  SpMat full_;
  Eigen::SparseLU<SpMat, Ordering> solver_;
};

void check_ordering(const std::string& backend, const std::string& ordering, std::initializer_list<const char*> valid) {
  for (const char* v : valid)
    if (ordering == v) return;
  std::string list;
  for (const char* v : valid) list += list.empty() ? v : std::string(", ") + v;
  throw Error(fmt::format("{}: unsupported ordering '{}' (valid: {})", backend, ordering, list));
}

}  // namespace

std::unique_ptr<LinearSolver> backends::make_eigen_simplicial(bool ldlt, const SolverOptions& options) {
  const std::string name = ldlt ? "eigen_simplicial_ldlt" : "eigen_simplicial_llt";
  check_ordering(name, options.ordering, {"default", "amd", "natural"});
  using Amd = Eigen::AMDOrdering<int>;
  using Natural = Eigen::NaturalOrdering<int>;
  if (options.ordering == "natural") {
    if (ldlt) return std::make_unique<EigenSimplicial<Eigen::SimplicialLDLT, Natural>>("natural");
    return std::make_unique<EigenSimplicial<Eigen::SimplicialLLT, Natural>>("natural");
  }
  if (ldlt) return std::make_unique<EigenSimplicial<Eigen::SimplicialLDLT, Amd>>("amd");
  return std::make_unique<EigenSimplicial<Eigen::SimplicialLLT, Amd>>("amd");
}

std::unique_ptr<LinearSolver> backends::make_eigen_sparse_lu(const SolverOptions& options) {
  check_ordering("eigen_sparse_lu", options.ordering, {"default", "colamd", "amd", "natural"});
  if (options.ordering == "amd") return std::make_unique<EigenSparseLU<Eigen::AMDOrdering<int>>>("amd");
  if (options.ordering == "natural") return std::make_unique<EigenSparseLU<Eigen::NaturalOrdering<int>>>("natural");
  return std::make_unique<EigenSparseLU<Eigen::COLAMDOrdering<int>>>("colamd");
}

}  // namespace db
