#pragma once
//! The quadratic energy with fixed variables that every deformer minimizes, in the precompute / solve shape of
//! libigl's min_quad_with_fixed: the normal system of a built energy (systems/normal_system.h,
//! systems/lri_system.h) is factored once per edit, and each frame gives the hard values x_h and the soft
//! targets u and gets the unknowns x_u:
//!
//!   K x_u = g - C x_h + W u,   g = g0 = A_u^T b (or a linear term given per frame),  W = w^2 on soft unknowns.
//!
//! Precompute (MinQuadWithFixed::precompute): the backend by name for the system's build (resolve_solver),
//! analyze + factorize of K (factorize_consuming when the caller has no further use for K), or factorize_dense
//! of the dense build's full K; the phase times and a SystemReport. Solve: form_rhs, as the build keeps its
//! system (the naive build's kept A^T: A_u^T (b - A_h x_h), as the thesis' first version; otherwise g0 - C x_h;
//! then W u), and solve. Optional per-frame fast path (set_varying, set_base): the rows that can change between
//! frames and the base right-hand side go to the solver (LinearSolver::set_base_rhs), which may redo only their
//! part of the forward substitution.
//!
//! A rank share (NormalSystem::parts > 1, build_structured_share) goes to a backend that sums the ranks' matrices
//! and right-hand sides (SolverOptions::rank_shares: mumps on as many ranks); each rank's right-hand side holds
//! its own rows only, and every rank gets the whole solution.
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "solvers/base/types.h"
#include "solvers/linear_solver.h"
#include "systems/normal_system.h"

namespace db {

//! One factored system as the deformers report it.
struct SystemReport {
  std::string name;  //!< e.g. "positions" or "frames"
  std::string backend;  //!< the solver backend that factored it (resolve_solver: never empty)
  std::size_t n = 0, nnz = 0;
  std::size_t matrix_bytes = 0;  //!< the system matrix handed to the solver
  FactorStats factor;
  std::vector<std::pair<std::string, std::size_t>> held_bytes;  //!< matrices held by the build
};

//! The backend that factors a build: `name`, or the build's default when `name` is empty (dense_llt for the
//! dense build, multifrontal for the sparse builds). Dense backends may factor the sparse builds too (they
//! expand K; a reference on small systems); the dense build needs a dense backend.
//! \throw InputError naming both for a backend that takes sparse input only with the dense build; Error for an
//!        unknown name.
std::string resolve_solver(const std::string& name, Build build);

class MinQuadWithFixed {
 public:
  //! Takes the system over and factors it. `solver`: a registry name or empty (resolve_solver). The dense
  //! build is not ordered (options.ordering is not passed to its backend). `consume_matrix`: hand a sparse K to
  //! the solver (factorize_consuming), leaving system().K empty; the dense build's K always goes. `name` names
  //! the report. \throw InputError (resolve_solver), SolverError for a failed factorization, BudgetError.
  void precompute(NormalSystem sys, const Unknowns& unk, const std::string& name, const std::string& solver,
                  const SolverOptions& options, bool consume_matrix) {
    analyze(std::move(sys), unk, name, solver, options);
    factorize(consume_matrix);
  }
  //! precompute in its two steps, for a caller that analyzes several systems before it factors any (LRI: its
  //! allocations, and so its peak memory, keep that order). The dense build's analyze only takes the system.
  void analyze(NormalSystem sys, const Unknowns& unk, const std::string& name, const std::string& solver,
               const SolverOptions& options);
  void factorize(bool consume_matrix);

  //! Turns on the per-frame fast path (sparse builds; the dense backends solve in full): the right-hand side
  //! may change between frames only in the rows of the unknowns `moving_unknowns` and in those coupled through
  //! C to the hard indices `moving_hard`. Until set_base, base_pending() is true.
  void set_varying(const std::vector<int>& moving_hard, const std::vector<int>& moving_unknowns);
  bool base_pending() const { return varying_ && !base_set_; }
  //! The base: the right-hand side of these values (form_rhs), handed to the solver with the varying rows.
  void set_base(const DenseMat& xh, const DenseMat& soft);

  //! The right-hand side of one frame. `xh`: the hard values, b#hard x cols (hard index h in rows
  //! b*h .. b*h+b-1, as in Unknowns); `soft`: the soft targets, b#soft x cols, in the order of
  //! Unknowns::soft_vertices. `linear`: when given, adds this frame's linear term, in place of g0, to the zeroed
  //! right-hand side it is handed (LRI's positions: A_u^T t for this frame's targets t).
  void form_rhs(const DenseMat& xh, const DenseMat& soft, const std::function<void(DenseMat&)>& linear = {});
  //! The right-hand side of these values into `out`, with the constant term (g0; the naive build's A_u^T b) when
  //! `constant`, or only the part linear in (xh, soft) without it: -C xh + W u (the naive build: -A_u^T A_h xh +
  //! W u), with as many columns as xh and soft have (a handle-response basis, systems/handle_response.h).
  void rhs_of(const DenseMat& xh, const DenseMat& soft, bool constant, DenseMat& out) const;
  //! X = K^-1 B for any number of columns in one multi-right-hand-side solve (LinearSolver::solve), never the
  //! per-frame fast path. \throw SolverError from the backend.
  void solve_columns(const DenseMat& B, DenseMat& X) const { solver_->solve(B, X); }
  //! x_u (b#unknowns x cols) of the last form_rhs (the fast path's solve_changed once set_base was given).
  //! \throw SolverError from the backend, e.g. for a non-finite result (LinearSolver::solve).
  void solve(DenseMat& xu);
  //! Scalar unknowns (rows of x_u) and hard values (rows of x_h).
  int num_unknown_rows() const { return static_cast<int>(report_.n); }

  //! The system as built; after factorize(true) its K is empty (the solver took it), and a dense K_dense always.
  const NormalSystem& system() const { return sys_; }
  const SystemReport& report() const { return report_; }
  SystemReport& report() { return report_; }
  double analyze_seconds() const { return analyze_seconds_; }
  double factorize_seconds() const { return factorize_seconds_; }

 private:
  //! out -= C xh (skipped for an empty xh), out += W u.
  void add_constraints(const DenseMat& xh, const DenseMat& soft, DenseMat& out) const;
  //! A rank share's right-hand side: zero outside its own rows, so the ranks' right-hand sides sum to the
  //! whole system's (the solver sums them). The whole system: nothing.
  void keep_own_rows(DenseMat& out) const;

  NormalSystem sys_;
  std::unique_ptr<LinearSolver> solver_;
  SystemReport report_;
  std::vector<int> soft_unknowns_;  // per soft vertex (Unknowns::soft_vertices order): its unknown index
  int num_hard_ = 0;
  double w2_ = 1.0;
  double analyze_seconds_ = 0, factorize_seconds_ = 0;
  std::vector<int> varying_rows_;
  bool varying_ = false, base_set_ = false;
  DenseMat rhs_;
};

}  // namespace db
