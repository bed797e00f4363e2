//! "umfpack": UMFPACK multifrontal LU of the full symmetric matrix (umfpack_di_* C API).
#include <limits>
#include <vector>

#include <fmt/format.h>
#include <umfpack.h>

#include "solvers/base/error.h"
#include "solvers/backends.h"
#include "solvers/solver_util.h"

namespace db {
namespace {

using namespace solver_util;

std::string status_text(int status) {
  switch (status) {
    case UMFPACK_OK: return "UMFPACK_OK";
    case UMFPACK_WARNING_singular_matrix: return "singular matrix";
    case UMFPACK_WARNING_determinant_underflow: return "determinant underflow";
    case UMFPACK_WARNING_determinant_overflow: return "determinant overflow";
    case UMFPACK_ERROR_out_of_memory: return "out of memory";
    case UMFPACK_ERROR_invalid_Numeric_object: return "invalid Numeric object";
    case UMFPACK_ERROR_invalid_Symbolic_object: return "invalid Symbolic object";
    case UMFPACK_ERROR_argument_missing: return "argument missing";
    case UMFPACK_ERROR_n_nonpositive: return "n nonpositive";
    case UMFPACK_ERROR_invalid_matrix: return "invalid matrix";
    case UMFPACK_ERROR_different_pattern: return "different pattern";
    case UMFPACK_ERROR_invalid_system: return "invalid system";
    case UMFPACK_ERROR_invalid_permutation: return "invalid permutation";
    case UMFPACK_ERROR_ordering_failed: return "ordering failed";
    case UMFPACK_ERROR_internal_error: return "internal error";
    default: return fmt::format("status {}", status);
  }
}

const char* ordering_text(double used) {
  switch (int(used)) {
    case UMFPACK_ORDERING_CHOLMOD: return "cholmod";
    case UMFPACK_ORDERING_AMD: return "amd";
    case UMFPACK_ORDERING_GIVEN: return "given";
    case UMFPACK_ORDERING_METIS: return "metis";
    case UMFPACK_ORDERING_BEST: return "best";
    case UMFPACK_ORDERING_NONE: return "natural";
    case UMFPACK_ORDERING_USER: return "user";
    default: return "unknown";
  }
}

class UmfpackSolver final : public LinearSolver {
 public:
  explicit UmfpackSolver(const SolverOptions& options) {
    umfpack_di_defaults(control_);
    const std::string& o = options.ordering;
    if (o == "default") {
      // UMFPACK's own default (CHOLMOD: AMD, METIS when fill is high)
    } else if (o == "amd") {
      control_[UMFPACK_ORDERING] = UMFPACK_ORDERING_AMD;
    } else if (o == "metis") {
      control_[UMFPACK_ORDERING] = UMFPACK_ORDERING_METIS;
    } else if (o == "natural") {
      control_[UMFPACK_ORDERING] = UMFPACK_ORDERING_NONE;
    } else {
      throw Error(fmt::format("umfpack: unsupported ordering '{}' (valid: default, amd, metis, natural)", o));
    }
  }
  UmfpackSolver(const UmfpackSolver&) = delete;
  UmfpackSolver& operator=(const UmfpackSolver&) = delete;
  ~UmfpackSolver() override { release(); }

  std::string name() const override { return "umfpack"; }

  void analyze(const SpMat& upper_in) override {
    check_square(upper_in, name());
    SpMat storage;
    const SpMat& upper = compressed(upper_in, storage);
    release();
    full_from_upper(upper).swap(full_);
    const int n = int(full_.rows());
    const int status = umfpack_di_symbolic(n, n, full_.outerIndexPtr(), full_.innerIndexPtr(), full_.valuePtr(),
                                           &symbolic_, control_, info_);
    if (status != UMFPACK_OK) {
      release();
      throw SolverError(fmt::format("umfpack: symbolic analysis failed: {}", status_text(status)));
    }
    guard_.remember(upper);
    stats_ = FactorStats{};
    stats_.n = std::size_t(n);
    stats_.nnz_matrix = std::size_t(upper.nonZeros());
    stats_.ordering_used = ordering_text(info_[UMFPACK_ORDERING_USED]);
  }

  void factorize(const SpMat& upper_in) override {
    SpMat storage;
    const SpMat& upper = compressed(upper_in, storage);
    if (!symbolic_)
      analyze(upper);
    else
      guard_.check(upper, name());
    check_finite_values(upper, name());
    if (numeric_) umfpack_di_free_numeric(&numeric_);
    full_from_upper(upper).swap(full_);  // same pattern as at analyze (guarded); UMFPACK's solve refines against it
    const int status = umfpack_di_numeric(full_.outerIndexPtr(), full_.innerIndexPtr(), full_.valuePtr(), symbolic_,
                                          &numeric_, control_, info_);
    if (status != UMFPACK_OK) {
      if (numeric_) umfpack_di_free_numeric(&numeric_);
      throw SolverError(fmt::format("umfpack: numeric factorization failed: {}", status_text(status)));
    }
    // UMFPACK_RCOND is min/max |diag(U)| of the (row-scaled) factor: at rounding level the matrix is
    // singular to working precision and the solution would be noise.
    const double rcond = info_[UMFPACK_RCOND];
    if (!(rcond >= singular_pivot_bound(std::size_t(full_.rows())))) {
      umfpack_di_free_numeric(&numeric_);
      throw SolverError(fmt::format("umfpack: matrix numerically singular (pivot ratio {:.3g})", rcond));
    }
    int lnz = 0, unz = 0, nrow = 0, ncol = 0, nz_udiag = 0;
    umfpack_di_get_lunz(&lnz, &unz, &nrow, &ncol, &nz_udiag, numeric_);
    stats_.nnz_factor = std::size_t(lnz) + std::size_t(unz) - std::size_t(nrow);  // diagonal counted once
    stats_.flops = info_[UMFPACK_FLOPS];
    stats_.factor_bytes = std::size_t(info_[UMFPACK_NUMERIC_SIZE] * info_[UMFPACK_SIZE_OF_UNIT]);
    wi_.resize(std::size_t(nrow));
    w_.resize(5 * std::size_t(nrow));  // 5n with iterative refinement (Control[UMFPACK_IRSTEP] > 0)
  }

  void solve(const DenseMat& B, DenseMat& X) override {
    if (!numeric_) throw SolverError("umfpack: solve() before a successful factorize()");
    check_rhs(B, Index(stats_.n), name());
    X.resize(B.rows(), B.cols());
    for (Eigen::Index c = 0; c < B.cols(); ++c) {
      const int status = umfpack_di_wsolve(UMFPACK_A, full_.outerIndexPtr(), full_.innerIndexPtr(), full_.valuePtr(),
                                           X.col(c).data(), B.col(c).data(), numeric_, control_, info_, wi_.data(),
                                           w_.data());
      if (status != UMFPACK_OK)
        throw SolverError(fmt::format("umfpack: solve failed: {}", status_text(status)));
    }
    check_finite_result(X, name());
  }

  FactorStats stats() const override { return stats_; }

 private:
  void release() {
    if (numeric_) umfpack_di_free_numeric(&numeric_);
    if (symbolic_) umfpack_di_free_symbolic(&symbolic_);
  }

  double control_[UMFPACK_CONTROL];
  double info_[UMFPACK_INFO];
  void* symbolic_ = nullptr;
  void* numeric_ = nullptr;
  SpMat full_;  // UMFPACK takes the full matrix; it is also needed by the refinement steps of solve
  std::vector<int> wi_;
  std::vector<double> w_;
  PatternGuard guard_;
  FactorStats stats_;
};

}  // namespace

std::unique_ptr<LinearSolver> backends::make_umfpack(const SolverOptions& options) {
  return std::make_unique<UmfpackSolver>(options);
}

}  // namespace db
