//! "mumps": MUMPS's multifrontal LDL^T for symmetric positive definite matrices (SYM=1) on this process alone
//! (MPI_COMM_SELF, centralized input), with MUMPS's orderings and its out-of-core factor. The same instance
//! settings as the distributed run (mumps_instance.h); MPI is initialized on first use (mumps_mpi.h).
#include <algorithm>
#include <memory>
#include <vector>

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "solvers/backends.h"
#include "solvers/mumps_instance.h"
#include "solvers/mumps_mpi.h"
#include "solvers/ordering/graph_ordering.h"
#include "solvers/solver_util.h"

namespace db {
namespace {

using namespace solver_util;

class MumpsSolver final : public LinearSolver {
 public:
  explicit MumpsSolver(const SolverOptions& options) : options_(options) {
    check_options(options, name());
    if (options.rank_shares != 1)
      throw Error(fmt::format("mumps: the system comes in {} rank shares, but this process runs alone (start it on "
                              "that many ranks)", options.rank_shares));
  }

  std::string name() const override { return "mumps"; }

  void analyze(const SpMat& upper_in) override {
    check_square(upper_in, name());
    SpMat storage;
    const SpMat& input = compressed(upper_in, storage);
    const SpMat& upper = mumps::upper_triangle(input, lower_free_);
    mumps_ = std::make_unique<mumps::Instance>(MPI_COMM_SELF, options_, name());
    coordinates(upper);
    std::vector<int> perm_in;
    if (mumps_->given_ordering()) perm_in = given_positions(upper);
    DMUMPS_STRUC_C& id = mumps_->id();
    id.n = MUMPS_INT(upper.cols());
    id.nnz = MUMPS_INT8(irn_.size());
    id.irn = irn_.data();
    id.jcn = jcn_.data();
    id.a = nullptr;
    mumps_->analyze(&perm_in);
    guard_.remember(input);
    stats_ = FactorStats{};
    stats_.n = std::size_t(upper.cols());
    stats_.nnz_matrix = std::size_t(upper.nonZeros());
    stats_.factor_on_disk = !options_.factor_dir.empty();
    stats_.ordering_used = mumps_->ordering_used();
  }

  void factorize(const SpMat& upper_in) override {
    SpMat storage;
    const SpMat& upper = mumps::upper_triangle(prepare_factorize(*this, guard_, upper_in, storage), lower_free_);
    // The COO coordinates were laid out in the CSC order of this pattern (guarded): the values are passed as they
    // lie, without a copy.
    const DenseVec d = diagonal_of(upper);
    mumps_->set_diagonal(std::vector<double>(d.data(), d.data() + d.size()));
    mumps_->id().a = const_cast<double*>(upper.valuePtr());
    mumps_->factorize(options_.pivot_singularity_test);
    mumps_->id().a = nullptr;
    mumps_->fill_stats(stats_);
  }

  void solve(const DenseMat& B, DenseMat& X) override {
    if (!mumps_ || !mumps_->factored()) throw SolverError("mumps: solve() before a successful factorize()");
    check_rhs(B, Index(stats_.n), name());
    X = B;
    DMUMPS_STRUC_C& id = mumps_->id();
    id.nrhs = MUMPS_INT(X.cols());
    id.lrhs = MUMPS_INT(X.rows());
    id.rhs = X.data();
    mumps_->solve();
    id.rhs = nullptr;
    check_finite_result(X, name());
  }

  FactorStats stats() const override { return stats_; }

 private:
  //! 1-based COO coordinates in CSC order.
  void coordinates(const SpMat& upper) {
    irn_.resize(std::size_t(upper.nonZeros()));
    jcn_.resize(irn_.size());
    for (Index j = 0; j < upper.outerSize(); ++j)
      for (int p = upper.outerIndexPtr()[j]; p < upper.outerIndexPtr()[j + 1]; ++p) {
        irn_[std::size_t(p)] = upper.innerIndexPtr()[p] + 1;
        jcn_[std::size_t(p)] = MUMPS_INT(j + 1);
      }
  }

  //! PERM_IN for a given ordering: the 1-based position of each unknown. "natural": the identity; "metis": this
  //! project's METIS order of the block graph (solvers/ordering), expanded to the unknowns.
  std::vector<int> given_positions(const SpMat& upper) const {
    const int n = int(upper.cols());
    std::vector<int> pos(static_cast<std::size_t>(n));
    if (options_.ordering == "natural") {
      for (int i = 0; i < n; ++i) pos[std::size_t(i)] = i + 1;
      return pos;
    }
    const int b = options_.block_size > 1 && n % options_.block_size == 0 ? options_.block_size : 1;
    const BlockGraph g = block_graph(upper, b);
    const std::vector<int> P = metis_permutation({g.nb, g.Ap.data(), g.Ai.data()});  // P[new] = old
    for (int k = 0; k < g.nb; ++k)
      for (int c = 0; c < b; ++c) pos[std::size_t(b * P[std::size_t(k)] + c)] = b * k + c + 1;
    return pos;
  }

  SolverOptions options_;
  std::unique_ptr<mumps::Instance> mumps_;
  std::vector<MUMPS_INT> irn_, jcn_;
  SpMat lower_free_;  //!< the input without what lies below its diagonal, when it had any
  PatternGuard guard_;
  FactorStats stats_;
};

}  // namespace

std::vector<std::string> backends::mumps_orderings() { return mumps::orderings(); }

std::vector<std::string> backends::mumps_refined_orderings() {
  std::vector<std::string> o = mumps::orderings();
  o.erase(std::remove(o.begin(), o.end(), "metis"), o.end());
  return o;
}

std::unique_ptr<LinearSolver> backends::make_mumps(const SolverOptions& options) {
  // Under a launcher with several ranks every rank takes part (mumps_ranks_solver.cpp).
  if (mpi::launched() && mpi::size() > 1) return make_mumps_on_ranks(options);
  return std::make_unique<MumpsSolver>(options);
}

}  // namespace db
