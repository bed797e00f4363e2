//! "mumps" under a launcher with more than one rank (make_mumps picks it): the LinearSolver contract on every
//! rank of MPI_COMM_WORLD at once. Every rank runs the same caller and calls analyze / factorize / solve in the
//! same order, and every rank gets the solution (broadcast from rank 0), so the callers on all ranks go on in
//! step. Two inputs (SolverOptions::rank_shares): every rank passes the same, whole system and MUMPS gets each
//! rank's share of its columns; or each rank passes only its own share (rank-local assembly), the system being
//! the sum of the ranks' matrices and right-hand sides. Either way MUMPS takes distributed assembled input
//! (DistributedMumps).
//! "mumps_refined" (any number of ranks): each rank also keeps its share of the columns, and every solve is
//! refined (multifrontal/refinement.h) on every rank in step: the products with A are the ranks' shares' products
//! summed on rank 0 (the extended residual in double-double, rounded once there) and broadcast, the
//! preconditioner is MUMPS's collective solve; so every rank holds bitwise the same vectors and takes the same
//! steps. Why: at 416k TF the plain distributed solve was 1.6e-2 of the bounding-box diagonal from the exact
//! solution (results/records/2026-11-24-mumps-ranks/), and a residual computed in double cannot see that error (refinement.h).
#include <cstdint>
#include <memory>
#include <vector>

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "solvers/backends.h"
#include "solvers/mumps_distributed.h"
#include "solvers/mumps_instance.h"
#include "solvers/mumps_mpi.h"
#include "solvers/multifrontal/refinement.h"
#include "solvers/solver_util.h"

namespace db {
namespace {

using namespace solver_util;
using multifrontal::RowMajorMat;

class MumpsOnRanks final : public LinearSolver {
 public:
  MumpsOnRanks(const SolverOptions& options, bool refined)
      : options_(options), shares_(options.rank_shares > 1), refined_(refined) {
    check_options(options, name());
    if (shares_ && options.rank_shares != mpi::size())
      throw Error(fmt::format("mumps: the system comes in {} rank shares, but {} ranks run", options.rank_shares,
                              mpi::size()));
  }

  std::string name() const override { return refined_ ? "mumps_refined" : "mumps"; }

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
    if (!factored_) throw SolverError(fmt::format("{}: solve() before a successful factorize()", name()));
    check_rhs(B, Index(stats_.n), name());
    // Rank 0's right-hand sides are solved (every rank's are the same, or their shares summed there); the
    // solution is broadcast.
    X = B;
    if (shares_) mpi::sum_to_root(X.data(), std::size_t(X.size()));
    if (refined_) {
      broadcast(X);
      solve_refined(X);
      return;
    }
    if (mpi::rank() != 0) X = DenseMat();
    mumps_->solve(X);
    broadcast(X);
  }

  FactorStats stats() const override { return stats_; }

 private:
  //! The values of this rank's columns, in the order analyze() passed their coordinates (analyzing first when
  //! nothing was; the pattern checked against the analyzed one, the values finite); with refinement, the share
  //! kept too.
  std::vector<double> own_values(const SpMat& upper_in) {
    SpMat storage, lower_free;
    const SpMat& upper = mumps::upper_triangle(prepare_factorize(*this, guard_, upper_in, storage), lower_free);
    keep_share(upper);
    const int* p = upper.outerIndexPtr();
    return std::vector<double>(upper.valuePtr() + p[c0_], upper.valuePtr() + p[c1_]);
  }

  void factorize_values(std::vector<double> values) {
    factored_ = false;
    mumps_->factorize(std::move(values));
    factored_ = true;
    stats_ = mumps_->stats();
  }

  //! With refinement, this rank's share of the upper triangle (its columns) as analyzed, for the products.
  void keep_share(const SpMat& upper) {
    if (!refined_) return;
    share_ = upper;
    if (!shares_) share_.prune([this](Index, Index c, double) { return c >= c0_ && c < c1_; });
    share_.makeCompressed();
  }

  //! Rank 0's X (n x k) copied to every rank.
  void broadcast(DenseMat& X) const {
    const Index n = Index(stats_.n);
    std::vector<int> cols{int(X.cols())};
    mpi::broadcast(cols);
    std::vector<double> x(X.data(), X.data() + (mpi::rank() == 0 ? X.size() : 0));
    mpi::broadcast(x);
    X = Eigen::Map<const DenseMat>(x.data(), n, cols[0]);
  }

  //! X: B on every rank in, A^-1 B out (multifrontal/refinement.h), every rank in step.
  void solve_refined(DenseMat& X) {
    const RowMajorMat b = X;
    RowMajorMat y;
    const auto precondition = [this](RowMajorMat& v) {
      DenseMat w = v;
      if (mpi::rank() != 0) w = DenseMat();
      mumps_->solve(w);
      broadcast(w);
      v = w;
    };
    const auto product = [this](const RowMajorMat& v, RowMajorMat& out) {
      multifrontal::symmetric_product(share_, v, out);
      mpi::sum_to_root(out.data(), std::size_t(out.size()));
      broadcast_rows(out);
    };
    const auto residual = [this](const RowMajorMat& v, const RowMajorMat& rhs, RowMajorMat& out) {
      std::vector<double> low;
      const RowMajorMat mine = mpi::rank() == 0 ? rhs : RowMajorMat::Zero(rhs.rows(), rhs.cols());
      multifrontal::extended_residual_parts(share_, v, mine, out, low);
      mpi::sum_double_double_to_root(out.data(), low.data(), std::size_t(out.size()));
      if (mpi::rank() == 0)
        for (Index k = 0; k < out.size(); ++k) out.data()[k] += low[std::size_t(k)];
      broadcast_rows(out);
    };
    const multifrontal::Refinement r = multifrontal::refine({product, residual}, precondition, b, y, options_.tolerance,
                                                            options_.max_iterations, name());
    stats_.iterations = r.iterations;
    stats_.achieved_tolerance = r.residual;
    stats_.last_correction = r.last_correction;
    X = y;
  }

  //! Rank 0's `m` on every rank (same shape everywhere).
  static void broadcast_rows(RowMajorMat& m) {
    std::vector<double> v(m.data(), m.data() + m.size());
    mpi::broadcast(v);
    m = Eigen::Map<const RowMajorMat>(v.data(), m.rows(), m.cols());
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
  bool refined_ = false;  //!< mumps_refined
  SpMat share_;           //!< refined: this rank's columns of the upper triangle
  std::unique_ptr<DistributedMumps> mumps_;
  Index c0_ = 0, c1_ = 0;  //!< this rank's columns
  bool factored_ = false;
  PatternGuard guard_;
  FactorStats stats_;
};

}  // namespace

std::unique_ptr<LinearSolver> backends::make_mumps_on_ranks(const SolverOptions& options, bool refined) {
  return std::make_unique<MumpsOnRanks>(options, refined);
}

}  // namespace db
