#include "solvers/least_squares.h"

#include <cstring>
#include <vector>

#include <SuiteSparseQR.hpp>
#include <fmt/format.h>

#include "solvers/base/error.h"
#include "solvers/ordering/cholmod_views.h"
#include "solvers/solver_util.h"

namespace db {

struct SpqrLeastSquares::Impl {
  int ordering = SPQR_ORDERING_DEFAULT;
  cholmod_common cc{};
  SuiteSparseQR_factorization<double>* qr = nullptr;
  FactorStats stats;
  Index m = 0, n = 0;

  Impl() {
    cholmod_l_start(&cc);  // SPQR works on the SuiteSparse_long interface
    cc.print = 0;
  }
  ~Impl() {
    free_qr();
    cholmod_l_finish(&cc);
  }
  void free_qr() {
    if (qr) SuiteSparseQR_free<double>(&qr, &cc);
  }
};

namespace {

const char* ordering_text(SuiteSparse_long used) {
  switch (used) {
    case SPQR_ORDERING_FIXED: return "fixed";
    case SPQR_ORDERING_NATURAL: return "natural";
    case SPQR_ORDERING_COLAMD: return "colamd";
    case SPQR_ORDERING_GIVEN: return "given";
    case SPQR_ORDERING_CHOLMOD: return "cholmod";
    case SPQR_ORDERING_AMD: return "amd";
    case SPQR_ORDERING_METIS: return "metis";
    default: return "unknown";
  }
}

}  // namespace

SpqrLeastSquares::SpqrLeastSquares(const std::string& ordering) : impl_(std::make_unique<Impl>()) {
  if (ordering == "default")
    impl_->ordering = SPQR_ORDERING_DEFAULT;
  else if (ordering == "colamd")
    impl_->ordering = SPQR_ORDERING_COLAMD;
  else if (ordering == "amd")
    impl_->ordering = SPQR_ORDERING_AMD;
  else if (ordering == "metis")
    impl_->ordering = SPQR_ORDERING_METIS;
  else if (ordering == "natural")
    impl_->ordering = SPQR_ORDERING_NATURAL;
  else
    throw Error(fmt::format("spqr: unknown ordering '{}' (valid: default, colamd, amd, metis, natural)", ordering));
}

SpqrLeastSquares::~SpqrLeastSquares() = default;

void SpqrLeastSquares::factorize(const SpMat& A_in) {
  Impl& d = *impl_;
  SpMat storage;
  const SpMat& A = solver_util::compressed(A_in, storage);
  solver_util::check_finite_values(A, "spqr");
  if (A.rows() < A.cols())
    throw SolverError(fmt::format("spqr: least squares needs m >= n (got {} x {})", A.rows(), A.cols()));
  d.free_qr();
  d.m = Index(A.rows());
  d.n = Index(A.cols());
  // SPQR takes 64-bit indices only: copy the index arrays, view the values.
  std::vector<SuiteSparse_long> Ap(A.outerIndexPtr(), A.outerIndexPtr() + A.cols() + 1);
  std::vector<SuiteSparse_long> Ai(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros());
  cholmod_sparse view{};
  view.nrow = std::size_t(A.rows());
  view.ncol = std::size_t(A.cols());
  view.nzmax = std::size_t(A.nonZeros());
  view.p = Ap.data();
  view.i = Ai.data();
  view.x = const_cast<double*>(A.valuePtr());
  view.stype = 0;
  view.itype = CHOLMOD_LONG;
  view.xtype = CHOLMOD_REAL;
  view.dtype = CHOLMOD_DOUBLE;
  view.sorted = 1;
  view.packed = 1;
  const std::size_t before = d.cc.memory_inuse;
  d.qr = SuiteSparseQR_factorize<double>(d.ordering, SPQR_DEFAULT_TOL, &view, &d.cc);
  if (!d.qr) throw SolverError(fmt::format("spqr: factorization failed (CHOLMOD status {})", d.cc.status));
  if (d.qr->rank < d.n) {
    const auto rank = d.qr->rank;
    d.free_qr();
    throw SolverError(fmt::format("spqr: matrix rank deficient (rank estimate {} of {} columns)", rank, d.n));
  }
  d.stats = FactorStats{};
  d.stats.n = std::size_t(d.n);
  d.stats.nnz_matrix = std::size_t(A.nonZeros());
  d.stats.nnz_factor = std::size_t(d.cc.SPQR_istat[0]);
  d.stats.flops = d.cc.SPQR_flopcount;
  d.stats.factor_bytes = d.cc.memory_inuse > before ? d.cc.memory_inuse - before : 0;
  d.stats.ordering_used = ordering_text(d.cc.SPQR_istat[7]);
}

void SpqrLeastSquares::solve(const DenseMat& B, DenseMat& X) {
  Impl& d = *impl_;
  if (!d.qr) throw SolverError("spqr: solve() before a successful factorize()");
  if (B.rows() != d.m) throw SolverError(fmt::format("spqr: right-hand side has {} rows, A has {}", B.rows(), d.m));
  cholmod_dense Bv = cholmod_dense_view(std::size_t(B.rows()), std::size_t(B.cols()), B.data());
  // x = E (R \ (Q^T b)): the least-squares solution of a full-rank A.
  cholmod_dense* Y = SuiteSparseQR_qmult<double>(SPQR_QTX, d.qr, &Bv, &d.cc);
  if (!Y) throw SolverError(fmt::format("spqr: Q^T B failed (CHOLMOD status {})", d.cc.status));
  cholmod_dense* Xc = SuiteSparseQR_solve<double>(SPQR_RETX_EQUALS_B, d.qr, Y, &d.cc);
  cholmod_l_free_dense(&Y, &d.cc);
  if (!Xc) throw SolverError(fmt::format("spqr: R solve failed (CHOLMOD status {})", d.cc.status));
  X.resize(d.n, B.cols());
  const double* x = static_cast<const double*>(Xc->x);
  for (Eigen::Index c = 0; c < B.cols(); ++c)
    std::memcpy(X.col(c).data(), x + std::size_t(c) * Xc->d, sizeof(double) * std::size_t(d.n));
  cholmod_l_free_dense(&Xc, &d.cc);
  solver_util::check_finite_result(X, "spqr");
}

FactorStats SpqrLeastSquares::stats() const { return impl_->stats; }

}  // namespace db
