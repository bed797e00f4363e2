//! "mumps" under a launcher with more than one rank (make_mumps picks it): the LinearSolver contract on every
//! rank of MPI_COMM_WORLD at once. Every rank runs the same caller and calls analyze / factorize / solve in the
//! same order, and every rank gets the solution (broadcast from rank 0), so the callers on all ranks go on in
//! step. Two inputs (SolverOptions::rank_shares): every rank passes the same, whole system and MUMPS gets each
//! rank's share of its columns; or each rank passes only its own share (rank-local assembly), the system being
//! the sum of the ranks' matrices and right-hand sides. Either way MUMPS takes distributed assembled input
//! (DistributedMumps).
#include <cstdint>
#include <memory>
#include <vector>

#include <fmt/format.h>

#include "core/error.h"
#include "solvers/backends.h"
#include "solvers/mumps_distributed.h"
#include "solvers/mumps_instance.h"
#include "solvers/mumps_mpi.h"
#include "solvers/solver_util.h"

namespace db {
namespace {

using namespace solver_util;

class MumpsOnRanks final : public LinearSolver {
 public:
  explicit MumpsOnRanks(const SolverOptions& options) : options_(options), shares_(options.rank_shares > 1) {
    check_options(options, name());
    if (shares_ && options.rank_shares != mpi::size())
      throw Error(fmt::format("mumps: the system comes in {} rank shares, but {} ranks run", options.rank_shares,
                              mpi::size()));
  }

  std::string name() const override { return "mumps"; }

  void analyze(const SpMat& upper_in) override {
    check_square(upper_in, name());
    SpMat storage, lower_free;
    const SpMat& input = compressed(upper_in, storage);
    const SpMat& upper = mumps::upper_triangle(input, lower_free);
    same_on_every_rank(upper);
    if (shares_) {  // this rank's share is its whole input
      c0_ = 0;
      c1_ = upper.cols();
    } else {
      const int b = options_.block_size > 1 && upper.cols() % options_.block_size == 0 ? options_.block_size : 1;
      const long long blocks = upper.cols() / b, r = mpi::rank(), N = mpi::size();
      c0_ = Index(b * (r * blocks / N));
      c1_ = Index(b * ((r + 1) * blocks / N));
    }
    std::vector<int> rows, cols;
    for (Index c = c0_; c < c1_; ++c)
      for (SpMat::InnerIterator it(upper, c); it; ++it) {
        rows.push_back(int(it.row()));
        cols.push_back(int(c));
      }
    mumps_ = std::make_unique<DistributedMumps>(options_);
    mumps_->analyze(upper.cols(), std::move(rows), std::move(cols));
    guard_.remember(input);
    factored_ = false;
    stats_ = mumps_->stats();
    stats_.factor_on_disk = !options_.factor_dir.empty();
  }

  void factorize(const SpMat& upper_in) override { factorize_values(own_values(upper_in)); }

  //! Each rank drops the whole matrix as soon as its share of the values is copied, before MUMPS factors: the
  //! rank's peak then holds its share and its part of the factor, not the whole matrix besides.
  void factorize_consuming(SpMat& upper) override {
    const ClearOnExit clear{upper};
    std::vector<double> values = own_values(upper);
    upper = SpMat();
    factorize_values(std::move(values));
  }

  void solve(const DenseMat& B, DenseMat& X) override {
    if (!factored_) throw SolverError("mumps: solve() before a successful factorize()");
    check_rhs(B, Index(stats_.n), name());
    // Rank 0's right-hand sides are solved (every rank's are the same, or their shares summed there); the
    // solution is broadcast.
    if (shares_) {
      X = B;
      mpi::sum_to_root(X.data(), std::size_t(X.size()));
      if (mpi::rank() != 0) X = DenseMat();
    } else {
      X = mpi::rank() == 0 ? B : DenseMat();
    }
    mumps_->solve(X);
    std::vector<double> x(X.data(), X.data() + X.size());
    mpi::broadcast(x);
    X = Eigen::Map<const DenseMat>(x.data(), B.rows(), B.cols());
  }

  FactorStats stats() const override { return stats_; }

 private:
  //! The values of this rank's columns, in the order analyze() passed their coordinates (analyzing first when
  //! nothing was; the pattern checked against the analyzed one, the values finite).
  std::vector<double> own_values(const SpMat& upper_in) {
    SpMat storage, lower_free;
    const SpMat& upper = mumps::upper_triangle(prepare_factorize(*this, guard_, upper_in, storage), lower_free);
    const int* p = upper.outerIndexPtr();
    return std::vector<double>(upper.valuePtr() + p[c0_], upper.valuePtr() + p[c1_]);
  }

  void factorize_values(std::vector<double> values) {
    factored_ = false;
    mumps_->factorize(std::move(values));
    factored_ = true;
    stats_ = mumps_->stats();
  }

  //! Ranks that built different systems (another mesh, another order of the unknowns) would factor a mixture:
  //! refused. Compared: the size and a hash of the pattern; of shares, which differ, the size only (the caller
  //! checks that the ranks numbered the unknowns alike).
  void same_on_every_rank(const SpMat& upper) const {
    const int n = int(upper.cols());
    const bool same = shares_ ? mpi::same_on_every_rank(&n, 1)
                              : mpi::same_on_every_rank(upper.outerIndexPtr(), std::size_t(n) + 1) &&
                                    mpi::same_on_every_rank(upper.innerIndexPtr(), std::size_t(upper.nonZeros()));
    if (!same)
      throw SolverError(fmt::format("mumps on ranks: the ranks passed {} (each rank must build {}: the same input and "
                                    "the same order of the unknowns)",
                                    shares_ ? "shares of different sizes" : "different matrices",
                                    shares_ ? "its share of the same system" : "the same system"));
  }

  SolverOptions options_;
  bool shares_ = false;  //!< each rank passes its share (SolverOptions::rank_shares)
  std::unique_ptr<DistributedMumps> mumps_;
  Index c0_ = 0, c1_ = 0;  //!< this rank's columns
  bool factored_ = false;
  PatternGuard guard_;
  FactorStats stats_;
};

}  // namespace

std::unique_ptr<LinearSolver> backends::make_mumps_on_ranks(const SolverOptions& options) {
  return std::make_unique<MumpsOnRanks>(options);
}

}  // namespace db
