//! "multifrontal": supernodal multifrontal Cholesky LL^T for systems of b x b blocks (TF: b = 3).
//!
//! Why a backend of our own next to CHOLMOD: on the large TF systems CHOLMOD's left-looking supernodal
//! factorization ran far below the BLAS's dgemm rate, and its symbolic analysis ran on the 3n-unknown matrix
//! (the solver study, experiments/solvers.cpp, compares the two; its report gives the rates). Here
//!  - the symbolic analysis is CHOLMOD's, run on the compressed block graph and expanded (symbolic.h);
//!  - the numeric phase is multifrontal: each supernode assembles a dense front from the matrix and its
//!    children's update matrices, then dpotrf, dtrsm and dsyrk/dgemm on column panels (front.h);
//!  - nothing above the diagonal is stored: a supernode's factor is a lower trapezoid in column panels, its
//!    update matrix a lower triangle (storage.h); full square blocks cost markedly more factor memory and twice
//!    the update memory;
//!  - independent subtrees of the assembly tree run on separate threads with a single-threaded BLAS, the
//!    few top fronts after them one at a time, each cut into tiles that a team of threads shares (front.h); the
//!    solves are split the same way (schedule.h, triangular_solve.h), their panel kernels hand-written (kernels.h);
//!  - out of core, the factor lives in a scratch file (storage.h: Mapping::on_file).
//! "multifrontal_mixed" is the same factorization with the factor then rounded to single precision
//! (float_factor.h) and the double one dropped; its solves are refined (refinement.h: double-double residuals,
//! CG corrections preconditioned by the float factor) until a correction is SolverOptions::tolerance of x. Out of
//! core, the double factor is staged in the scratch file and only the rounded one is held in memory. "multifrontal_refined" keeps the double factor and refines its
//! solves the same way: the accuracy reference (the exact solution of the double system, to the tolerance).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "solvers/base/resources.h"
#include "solvers/backends.h"
#include "solvers/multifrontal/float_factor.h"
#include "solvers/multifrontal/front.h"
#include "solvers/multifrontal/refinement.h"
#include "solvers/multifrontal/schedule.h"
#include "solvers/multifrontal/storage.h"
#include "solvers/multifrontal/symbolic.h"
#include "solvers/multifrontal/top_phase.h"
#include "solvers/multifrontal/triangular_solve.h"
#include "solvers/solver_util.h"

namespace db {
namespace {

using namespace solver_util;
using namespace multifrontal;

class MultifrontalSolver final : public LinearSolver {
 public:
  MultifrontalSolver(const SolverOptions& options, backends::Precision precision)
      : options_(options), mixed_(precision == backends::Precision::Mixed),
        refined_(precision != backends::Precision::Double) {
    check_options(options, name());
  }

  std::string name() const override {
    return mixed_ ? "multifrontal_mixed" : refined_ ? "multifrontal_refined" : "multifrontal";
  }
  void analyze(const SpMat& upper_in) override;
  void factorize(const SpMat& upper_in) override { factorize_impl(upper_in, nullptr); }
  void factorize_consuming(SpMat& upper) override {
    const ClearOnExit clear{upper};
    factorize_impl(upper, refined_ ? nullptr : &upper);  // the refinement keeps A
  }
  void solve(const DenseMat& B, DenseMat& X) override;
  void set_base_rhs(const DenseMat& B0, const std::vector<int>& rows) override;
  void solve_changed(const DenseMat& B, DenseMat& X) override;
  FactorStats stats() const override { return stats_; }

 private:
  //! `consumed`: the caller's matrix (the same object as upper_in), whose memory may be handed back as the
  //! factorization no longer needs it; null to leave the matrix alone.
  void factorize_impl(const SpMat& upper_in, SpMat* consumed);
  //! Upper triangle of P A P^T with sorted columns (MatrixChunk searches them).
  SpMat permuted(const SpMat& given) const;
  //! Factors every supernode of A by factor_plan_ into values_; false when a pivot failed (fronts says where).
  bool factor_tree(const SpMat& A, bool may_release, FrontFactorization& fronts);
  //! The supernodes `rows` reach in the forward substitution, and their columns, into reach_ / reach_columns_.
  void find_reach(const std::vector<int>& rows);

  int iperm(int i) const { return iperm_.empty() ? i : iperm_[std::size_t(i)]; }
  FactorView factor() const { return {S_, values_}; }
  void check_factored(const char* what) const {
    if (!factored_) throw SolverError(fmt::format("{}: {}() before a successful factorize()", name(), what));
  }
  //! y_ := P B (row-major).
  void load_rhs(const DenseMat& B);
  //! X := P^T y_.
  void store_solution(DenseMat& X) const;
  bool matches_base_outside_changing_rows(const DenseMat& B) const;
  //! Out of core: supernode s's FactorBlock leaves the resident set (done with it for now).
  void release_block(int s) const { factor().release(s); }
  std::size_t factor_bytes() const;
  //! SolverOptions::memory_budget against the resident bytes now plus the factor's and the update matrices' peak
  //! (update_peak), before any of them is allocated. \throw BudgetError.
  void check_memory_budget() const;
  //! Refined backends: keeps A (permuted) for the refinement; mixed: rounds the factor to float, drops the double.
  void keep_for_refinement(const SpMat& given, SpMat& perm_copy);

  SolverOptions options_;
  bool mixed_ = false, refined_ = false;
  FloatFactor float_;  //!< mixed: the factor in single precision
  SpMat kept_;         //!< refined backends: P A P^T (upper), the refinement's products
  Symbolic S_;
  //! The solves' plan for r right-hand sides: for at most as many threads as their work is worth (threads_worth),
  //! fewer where more would lengthen its critical path (shortest_plan); made on first use and kept (the same thread
  //! count gives the same plan, so the same bytes).
  const Plan& solve_plan(Index r);

  Plan factor_plan_;
  std::vector<int> claim_order_;  // factor_plan_'s subtree roots in the order the threads claim them
  TopTree top_tree_;              // factor_plan_'s top supernodes as a tree, with their subtrees' flops
  std::map<int, Plan> solve_plans_;  //!< by the most threads the work is worth
  std::vector<double> entries_;      //!< per supernode: factor entries, the solves' cost
  int threads_ = 1;
  Mapping values_;  //!< the FactorBlocks of all supernodes
  std::vector<double> pivots_;  //!< L_jj^2 per column, kept as the factorization goes (no pass over the factor)
  RowMajorMat y_;
  std::vector<RowMajorMat> acc_;
  std::vector<int> iperm_;  //!< inverse of S_.perm (empty: identity)
  // set_base_rhs(): the base right-hand side, its forward substitution, the rows that may change and the
  // supernodes (and their columns) they reach.
  DenseMat base_;
  RowMajorMat y0_;
  std::vector<char> changing_;
  std::vector<int> changing_rows_, reach_, reach_columns_;
  PatternGuard guard_;
  FactorStats stats_;
  bool factored_ = false;
};

void MultifrontalSolver::analyze(const SpMat& upper_in) {
  check_square(upper_in, name());
  SpMat storage;
  const SpMat& upper = compressed(upper_in, storage);
  const int n = int(upper.cols());
  const int b = options_.block_size > 1 && n % options_.block_size == 0 ? options_.block_size : 1;
  factored_ = false;
  values_.reset();
  base_.resize(0, 0);
  threads_ = std::clamp(worker_threads(), 1, 64);  // owner[] holds a thread index in a signed char
  S_ = analyze_blocks(upper, b, options_.ordering, options_.elimination_tree.get());
  std::vector<double> flops(std::size_t(S_.nsuper()));
  entries_.assign(std::size_t(S_.nsuper()), 0.0);
  for (int s = 0; s < S_.nsuper(); ++s) {
    flops[std::size_t(s)] = supernode_flops(S_, s);
    entries_[std::size_t(s)] = double(S_.xptr[std::size_t(s) + 1] - S_.xptr[std::size_t(s)]);
  }
  factor_plan_ = schedule(S_, threads_, flops);
  claim_order_ = claim_order(S_, factor_plan_, flops);
  top_tree_ = top_tree(S_, factor_plan_, flops);
  solve_plans_.clear();
  guard_.remember(upper);
  stats_ = FactorStats{};
  stats_.n = std::size_t(n);
  stats_.nnz_matrix = std::size_t(upper.nonZeros());
  stats_.nnz_factor = S_.nnz;
  stats_.flops = S_.flops;
  stats_.ordering_used = (options_.ordering == "default" ? std::string(default_ordering(b)) : options_.ordering) +
                         (b > 1 ? fmt::format("-block{}", b) : "");
  stats_.factor_bytes = factor_bytes();
  stats_.factor_on_disk = !options_.factor_dir.empty() && !mixed_;
  stats_.workspace_bytes = std::size_t(update_peak(S_, factor_plan_));
  stats_.top_flops = plan_counts(S_, factor_plan_, flops).top;
}

void MultifrontalSolver::factorize_impl(const SpMat& upper_in, SpMat* consumed) {
  SpMat storage;
  const SpMat& given = prepare_factorize(*this, guard_, upper_in, storage);
  const DenseVec diag = diagonal_of(given);  // for the pivot check, before any of the matrix is released
  factored_ = false;
  iperm_.assign(S_.perm.size(), 0);
  for (std::size_t k = 0; k < S_.perm.size(); ++k) iperm_[std::size_t(S_.perm[k])] = int(k);
  SpMat perm_copy;
  if (!S_.perm.empty()) {  // the analysis chose an order: factor P A P^T
    permuted(given).swap(perm_copy);
    if (consumed) *consumed = SpMat();  // the permuted copy holds all the factorization reads
  }
  const SpMat& A = S_.perm.empty() ? given : perm_copy;
  // Pages of A whose columns are consumed may be returned: ours (a copy), or the caller's when consumed.
  const bool may_release = !refined_ && (&A != &upper_in || consumed != nullptr);
  base_.resize(0, 0);  // a new factor invalidates the rest-pose forward substitution
  float_ = FloatFactor();
  kept_ = SpMat();
  values_.reset();
  check_memory_budget();
  values_ = options_.factor_dir.empty() ? Mapping(S_.xptr.back(), "the factor")
                                        : Mapping::on_file(S_.xptr.back(), "the factor", options_.factor_dir);
  pivots_.assign(std::size_t(S_.n), 0.0);
  std::int64_t failed = -1;
  {
    FrontFactorization fronts(S_, values_.get(), pivots_, stats_.workspace_bytes);  // its update matrices die with it
    if (!factor_tree(A, may_release, fronts)) failed = fronts.failed_column();
  }
  if (failed >= 0) {
    values_.reset();
    const int k = int(failed);
    const int orig = S_.perm.empty() ? k : S_.perm[std::size_t(k)];
    throw SolverError(fmt::format("multifrontal: matrix not positive definite (failed at column {} of {}, "
                                  "unknown {})",
                                  k, S_.n, orig));
  }
  stats_.min_pivot_ratio = check_pivots(pivots_, S_.perm.empty() ? nullptr : S_.perm.data(), diag, name(),
                                        options_.pivot_singularity_test);
  if (refined_) keep_for_refinement(given, perm_copy);
  factored_ = true;
  stats_.factor_bytes = factor_bytes();
}

void MultifrontalSolver::check_memory_budget() const {
  if (options_.memory_budget == 0 || !options_.factor_dir.empty()) return;  // out of core: not resident
  const double held = double(current_rss_bytes());
  const double factor = double(S_.xptr.back()) * sizeof(double);
  const double updates = double(stats_.workspace_bytes);
  // The mixed backend rounds the factor to float once the update matrices are gone, then drops the double one.
  const double added = std::max(factor + updates, mixed_ ? 1.5 * factor : 0.0);
  if (held + added <= double(options_.memory_budget)) return;
  throw BudgetError(fmt::format("{}: the factor ({:.1f} MB) and its update matrices (up to {:.1f} MB) beside the "
                                "{:.1f} MB this process holds would pass the memory budget of {:.1f} MB; not factored",
                                name(), factor / 1e6, updates / 1e6, held / 1e6,
                                double(options_.memory_budget) / 1e6));
}

void MultifrontalSolver::keep_for_refinement(const SpMat& given, SpMat& perm_copy) {
  if (mixed_) {
    float_ = FloatFactor(factor());
    values_.reset();
  }
  if (S_.perm.empty())
    kept_ = given;
  else
    kept_.swap(perm_copy);
}

SpMat MultifrontalSolver::permuted(const SpMat& given) const {
  std::vector<Eigen::Triplet<double, int>> t;
  t.reserve(std::size_t(given.nonZeros()));
  for (int j = 0; j < given.outerSize(); ++j)
    for (SpMat::InnerIterator it(given, j); it; ++it) {
      const int a = iperm_[std::size_t(it.row())], c = iperm_[std::size_t(j)];
      t.emplace_back(std::min(a, c), std::max(a, c), it.value());
    }
  SpMat P(given.rows(), given.cols());
  P.setFromTriplets(t.begin(), t.end());
  return P;
}

bool MultifrontalSolver::factor_tree(const SpMat& A, bool may_release, FrontFactorization& fronts) {
  std::atomic<bool> ok{true};
  Handover handover(S_, factor_plan_);
  const std::vector<int> counts = MatrixChunk::lower_counts(A);
  std::atomic<std::size_t> next{0};  // in claim_order_: the next subtree a thread takes
  run_subtrees(factor_plan_.subtrees.size(), worth_threads(S_.flops, Work::Dense), [&](std::size_t) {
    if (next.load() >= claim_order_.size()) return;  // another thread took every subtree
    Workspace ws(S_.n);
    MatrixChunk chunk;
    ColumnRelease release(A, may_release);
    for (std::size_t k; (k = next.fetch_add(1)) < claim_order_.size();) {
      const int root = claim_order_[k];
      release.start(S_.col0[std::size_t(S_.first[std::size_t(root)])]);
      for (int s = S_.first[std::size_t(root)], loaded = -1; s <= root; ++s) {
        if (s > loaded) {
          loaded = MatrixChunk::run_end(S_, s, root);
          chunk.load(A, counts, S_, s, loaded);
        }
        if (!ok.load(std::memory_order_relaxed) || !fronts.factor_supernode(chunk, s, ws)) {
          ok = false;
          return;
        }
        release_block(s);
        release.dead_before(S_.col0[std::size_t(s) + 1], s == root);
      }
      handover.finished(root, [&](int c, int p) { fronts.assemble_child(c, p, ws); });
    }
  });
  if (!ok) return false;
  fronts.close_pool();
  const auto top_start = std::chrono::steady_clock::now();
  // The top fronts' tiles on teams of as many threads in all as their work is worth, each tile a one-thread BLAS
  // call; no more than the cores this process may run on, since each step waits for its claimed tiles and a
  // thread sharing a core is descheduled mid-tile (the tiles, and so the factor, do not depend on the teams).
  const BlasOnOneThread one_thread;
  const bool done = run_top_phase(
      top_tree_, std::min(threads_worth(stats_.top_flops, Work::Dense, threads_), available_cores()),
      [&] { return std::make_unique<TopScratch>(S_.n, A, may_release); },
      [&](int s, Team& team, TopScratch& t) {
        t.release.start(S_.col0[std::size_t(s)]);
        t.chunk.load(A, counts, S_, s, s);
        if (!fronts.factor_supernode(t.chunk, s, t.ws, &team)) return false;
        release_block(s);
        t.release.dead_before(S_.col0[std::size_t(s) + 1], true);
        return true;
      });
  stats_.top_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - top_start).count();
  return done;
}

void MultifrontalSolver::solve(const DenseMat& B, DenseMat& X) {
  check_factored("solve");
  check_rhs(B, Index(S_.n), name());
  load_rhs(B);
  if (refined_) {
    const RowMajorMat b = y_;
    const auto precondition = [this](RowMajorMat& y) {
      if (mixed_) {
        float_.solve(S_, solve_plan(y.cols()), y, acc_);
      } else {
        forward_all(factor(), solve_plan(y.cols()), y, acc_);
        backward_all(factor(), solve_plan(y.cols()), y);
      }
    };
    const Refinement r = refine(refined_system(kept_), precondition, b, y_, options_.tolerance, options_.max_iterations,
                                name());
    stats_.iterations = r.iterations;
    stats_.achieved_tolerance = r.residual;
    stats_.last_correction = r.last_correction;
  } else {
    forward_all(factor(), solve_plan(y_.cols()), y_, acc_);
    backward_all(factor(), solve_plan(y_.cols()), y_);
  }
  store_solution(X);
}

const Plan& MultifrontalSolver::solve_plan(Index r) {
  const int most = threads_worth(solve_flops(S_, r), Work::Solve, threads_);
  auto it = solve_plans_.find(most);
  // A solve reads each factor entry once per direction: its threads are balanced by entries, not flops.
  if (it == solve_plans_.end()) {
    SolvePlan chosen = shortest_plan(S_, most, entries_);
    Plan plan = std::move(chosen.plan);
    // The top supernodes are shared by a team (the subtree groups are done by then), sized by solve_top_team.
    const double top = 2.0 * plan_counts(S_, plan, entries_).top * double(r);
    plan.top_team = solve_top_team(top, chosen.threads, available_cores());
    it = solve_plans_.emplace(most, std::move(plan)).first;
  }
  return it->second;
}

void MultifrontalSolver::set_base_rhs(const DenseMat& B0, const std::vector<int>& rows) {
  check_factored("set_base_rhs");
  check_rhs(B0, Index(S_.n), name());
  base_.resize(0, 0);
  if (refined_) return;  // no fast path: each frame is refined in full (solve_changed falls back to solve)
  std::vector<char> changing(std::size_t(S_.n), 0);
  for (int i : rows) {
    if (i < 0 || i >= S_.n) throw SolverError(fmt::format("{}: set_base_rhs(): row {} out of range", name(), i));
    changing[std::size_t(i)] = 1;
  }
  find_reach(rows);
  load_rhs(B0);
  forward_all(factor(), solve_plan(y_.cols()), y_, acc_);
  y0_ = y_;
  changing_ = std::move(changing);
  changing_rows_ = rows;
  base_ = B0;
}

void MultifrontalSolver::find_reach(const std::vector<int>& rows) {
  // Supernodes holding the changing rows and all their ancestors (ascending = postorder).
  std::vector<int> super_of(std::size_t(S_.n));
  for (int s = 0; s < S_.nsuper(); ++s)
    std::fill(super_of.begin() + S_.col0[std::size_t(s)], super_of.begin() + S_.col0[std::size_t(s) + 1], s);
  std::vector<char> reached(std::size_t(S_.nsuper()), 0);
  for (int i : rows)
    for (int s = super_of[std::size_t(iperm(i))]; s >= 0 && !reached[std::size_t(s)]; s = S_.parent[std::size_t(s)])
      reached[std::size_t(s)] = 1;
  reach_.clear();
  reach_columns_.clear();
  for (int s = 0; s < S_.nsuper(); ++s)
    if (reached[std::size_t(s)]) {
      reach_.push_back(s);
      for (int j = S_.col0[std::size_t(s)]; j < S_.col0[std::size_t(s) + 1]; ++j) reach_columns_.push_back(j);
    }
}

void MultifrontalSolver::solve_changed(const DenseMat& B, DenseMat& X) {
  check_factored("solve");
  check_rhs(B, Index(S_.n), name());
  if (base_.rows() != B.rows() || base_.cols() != B.cols() || !matches_base_outside_changing_rows(B)) {
    solve(B, X);
    return;
  }
  // L z = P (B - B0) has z = 0 outside the reached supernodes; y = y0 + z.
  y_ = y0_;
  for (int j : reach_columns_) y_.row(j).setZero();
  for (int i : changing_rows_)
    for (Index c = 0; c < B.cols(); ++c) y_(iperm(i), c) += B(i, c) - base_(i, c);
  SolveScratch tmp;
  const Plan& plan = solve_plan(y_.cols());
  {
    Team team(plan.top_team);  // for the top supernodes the changes reach, as in forward_all
    Team* top = team.size() > 1 ? &team : nullptr;
    for (int s : reach_) {
      const bool is_top = plan.owner[std::size_t(S_.col0[std::size_t(s)])] < 0;
      forward_supernode(factor(), s, y_, tmp, nullptr, is_top ? top : nullptr);
    }
  }
  for (int j : reach_columns_) y_.row(j) += y0_.row(j);
  backward_all(factor(), plan, y_);
  store_solution(X);
}

void MultifrontalSolver::load_rhs(const DenseMat& B) {
  const Index n = S_.n, r = B.cols();
  if (y_.rows() != n || y_.cols() != r) {
    y_.resize(n, r);
    advise_huge_pages(y_.data(), std::size_t(y_.size()) * sizeof(double));  // many columns: tens of MB, untouched
  }
  for (Index k = 0; k < n; ++k) {  // row by row: y_ is row-major, each row written once
    const Index i = S_.perm.empty() ? k : S_.perm[std::size_t(k)];
    for (Index c = 0; c < r; ++c) y_(k, c) = B(i, c);
  }
}

void MultifrontalSolver::store_solution(DenseMat& X) const {
  const Index n = S_.n, r = y_.cols();
  if (X.rows() != n || X.cols() != r) {
    X.resize(n, r);
    advise_huge_pages(X.data(), std::size_t(X.size()) * sizeof(double));
  }
  for (Index k = 0; k < n; ++k) {  // row by row: y_ is row-major, each row read once
    const Index i = S_.perm.empty() ? k : S_.perm[std::size_t(k)];
    for (Index c = 0; c < r; ++c) X(i, c) = y_(k, c);
  }
  check_finite_result(X, name());
}

bool MultifrontalSolver::matches_base_outside_changing_rows(const DenseMat& B) const {
  for (Index c = 0; c < B.cols(); ++c)
    for (Index k = 0; k < B.rows(); ++k)
      if (!changing_[std::size_t(k)] && B(k, c) != base_(k, c)) return false;
  return true;
}

std::size_t MultifrontalSolver::factor_bytes() const {
  const std::size_t ints = S_.perm.size() + S_.col0.size() + S_.rptr.size() + S_.rows.size() + S_.parent.size() +
                           S_.first.size() + S_.cptr.size() + S_.child.size();
  const std::size_t entry = mixed_ ? sizeof(float) : sizeof(double);
  return S_.xptr.back() * entry + ints * sizeof(int) + S_.xptr.size() * sizeof(std::size_t);
}

}  // namespace

std::unique_ptr<LinearSolver> backends::make_multifrontal(const SolverOptions& options, Precision precision) {
  return std::make_unique<MultifrontalSolver>(options, precision);
}

}  // namespace db
