#include "systems/min_quad_with_fixed.h"

#include <algorithm>

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "core/timer.h"

namespace db {

std::string resolve_solver(const std::string& name, Build build) {
  if (name.empty()) return build == Build::Dense ? "dense_llt" : "multifrontal";
  const SolverInfo info = solver_info(name);
  if (build == Build::Dense && info.family != "dense")
    throw InputError(fmt::format("the dense build needs a dense backend (dense_llt, lapack_potrf, dense_ldlt_bk or "
                                 "dense_lu); '{}' ({}) takes sparse input only",
                                 name, info.family));
  return name;
}

void MinQuadWithFixed::analyze(NormalSystem sys, const Unknowns& unk, const std::string& name,
                               const std::string& solver, const SolverOptions& options) {
  const std::string backend = resolve_solver(solver, sys.build);
  sys_ = std::move(sys);
  soft_unknowns_.clear();
  for (int v : unk.soft_vertices) soft_unknowns_.push_back(unk.unknown_of[v]);
  num_hard_ = unk.num_hard();
  w2_ = unk.soft_weight * unk.soft_weight;
  varying_ = base_set_ = false;
  analyze_seconds_ = factorize_seconds_ = 0;
  report_ = SystemReport{};
  report_.name = name;
  report_.backend = backend;
  report_.held_bytes = sys_.held_bytes;
  if (sys_.build == Build::Dense) {
    report_.n = static_cast<std::size_t>(sys_.K_dense.rows());
    report_.nnz = static_cast<std::size_t>(sys_.K_dense.size());
    report_.matrix_bytes = report_.nnz * sizeof(double);
    SolverOptions dense = options;
    dense.ordering = "default";  // nothing to order
    solver_ = make_solver(backend, dense);
    return;  // factorize_dense replaces analyze + factorize
  }
  report_.n = static_cast<std::size_t>(sys_.K.rows());
  report_.nnz = static_cast<std::size_t>(sys_.K.nonZeros());
  report_.matrix_bytes = sparse_bytes(sys_.K);
  SolverOptions so = options;
  so.rank_shares = sys_.parts;  // a share goes to a backend that sums the ranks' (mumps on as many ranks)
  so.elimination_tree = sys_.tree;
  solver_ = make_solver(backend, so);
  Timer t;
  solver_->analyze(sys_.K);
  analyze_seconds_ = t.seconds();
  if (sys_.parts > 1) report_.nnz = solver_->stats().nnz_matrix;  // every rank's share
}

void MinQuadWithFixed::factorize(bool consume_matrix) {
  Timer t;
  if (sys_.build == Build::Dense) solver_->factorize_dense(sys_.K_dense);
  else if (consume_matrix) solver_->factorize_consuming(sys_.K);
  else solver_->factorize(sys_.K);
  factorize_seconds_ = t.seconds();
  report_.factor = solver_->stats();
}

void MinQuadWithFixed::set_varying(const std::vector<int>& moving_hard, const std::vector<int>& moving_unknowns) {
  if (sys_.build == Build::Dense) return;
  const int b = sys_.block;
  std::vector<char> changes(report_.n, 0);
  for (int u : moving_unknowns)
    for (int c = 0; c < b; ++c) changes[static_cast<std::size_t>(b * u + c)] = 1;
  for (int h : moving_hard)
    for (int c = 0; c < b; ++c)
      for (SpMat::InnerIterator it(sys_.C, b * h + c); it; ++it) changes[static_cast<std::size_t>(it.row())] = 1;
  varying_rows_.clear();
  for (std::size_t i = 0; i < changes.size(); ++i)
    if (changes[i]) varying_rows_.push_back(static_cast<int>(i));
  varying_ = true;
  base_set_ = false;
}

void MinQuadWithFixed::set_base(const DenseMat& xh, const DenseMat& soft) {
  form_rhs(xh, soft);
  solver_->set_base_rhs(rhs_, varying_rows_);
  base_set_ = true;
}

void MinQuadWithFixed::form_rhs(const DenseMat& xh, const DenseMat& soft,
                                const std::function<void(DenseMat&)>& linear) {
  if (linear && sys_.At.size() > 0) throw Error("form_rhs: a system that keeps A^T forms its linear term itself");
  if (linear) {
    rhs_.setZero(static_cast<Eigen::Index>(report_.n), sys_.rhs_cols);
    linear(rhs_);
    add_constraints(xh, soft, rhs_);
    keep_own_rows(rhs_);
  } else {
    rhs_of(xh, soft, /*constant=*/true, rhs_);
  }
}

void MinQuadWithFixed::rhs_of(const DenseMat& xh, const DenseMat& soft, bool constant, DenseMat& out) const {
  const Eigen::Index n = static_cast<Eigen::Index>(report_.n);
  const Eigen::Index cols = constant ? sys_.rhs_cols : std::max(xh.cols(), soft.cols());
  if (sys_.At.size() > 0) {  // the naive build's kept A^T: a product with A^T per frame
    if (constant && num_hard_ > 0) out.noalias() = sys_.At * DenseMat(sys_.targets - sys_.Ah * xh);
    else if (constant) out.noalias() = sys_.At * sys_.targets;
    else if (num_hard_ > 0) out.noalias() = -(sys_.At * DenseMat(sys_.Ah * xh));
    else out.setZero(n, cols);
    add_constraints(DenseMat(), soft, out);
    return;
  }
  if (constant && sys_.g0.size() > 0) out = sys_.g0;
  else out.setZero(n, cols);
  add_constraints(xh, soft, out);
  keep_own_rows(out);
}

void MinQuadWithFixed::keep_own_rows(DenseMat& out) const {
  if (sys_.parts == 1) return;
  // C's and g0's other rows are zero already; the soft weights' and a linear term's are another share's.
  const Eigen::Index lo = Eigen::Index(sys_.block) * sys_.own_begin, hi = Eigen::Index(sys_.block) * sys_.own_end;
  out.topRows(lo).setZero();
  out.bottomRows(out.rows() - hi).setZero();
}

void MinQuadWithFixed::add_constraints(const DenseMat& xh, const DenseMat& soft, DenseMat& out) const {
  if (num_hard_ > 0 && xh.size() > 0) {
    if (sys_.build == Build::Dense) out.noalias() -= sys_.C_dense * xh;
    else out.noalias() -= sys_.C * xh;
  }
  const int b = sys_.block;
  for (std::size_t s = 0; s < soft_unknowns_.size(); ++s)
    for (int r = 0; r < b; ++r)
      for (Eigen::Index c = 0; c < out.cols(); ++c)
        out(b * soft_unknowns_[s] + r, c) += w2_ * soft(static_cast<Eigen::Index>(b * s + r), c);
}

void MinQuadWithFixed::solve(DenseMat& xu) {
  if (varying_) solver_->solve_changed(rhs_, xu);
  else solver_->solve(rhs_, xu);
  const FactorStats now = solver_->stats();  // iterative and mixed backends: this solve's iterations, residual
  report_.factor.iterations = now.iterations;
  report_.factor.achieved_tolerance = now.achieved_tolerance;
  report_.factor.last_correction = now.last_correction;
}

}  // namespace db
