#include "methods/lri.h"

#include <fmt/format.h>

#include "core/error.h"
#include "core/timer.h"

namespace db {
namespace {

// Frame row block of directed edge (i, j): residual u_j - R_ij^T u_i (u = one world component of [b1 b2 N]).
EdgeBlocks frame_blocks(const std::vector<Mat3>& F) {
  return [&F](int i, int j, int, double* P, double* Q) {
    const Mat3 R = frame_connection(F[i], F[j]);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        P[r * 3 + c] = -R(c, r);
        Q[r * 3 + c] = r == c ? 1.0 : 0.0;
      }
  };
}

// Position row block of directed edge (i, j): residual x_j - x_i - target.
EdgeBlocks position_blocks() {
  return [](int, int, int, double* P, double* Q) {
    P[0] = -1.0;
    Q[0] = 1.0;
  };
}

SystemReport report(const char* name, const EdgeSystem& sys, const LinearSolver& solver) {
  SystemReport r;
  r.name = name;
  r.n = static_cast<std::size_t>(sys.K.rows());
  r.nnz = static_cast<std::size_t>(sys.K.nonZeros());
  r.matrix_bytes = sparse_bytes(sys.K);
  r.factor = solver.stats();
  r.held_bytes = sys.held_bytes;
  return r;
}

}  // namespace

LriDeformer::LriDeformer(const Mesh& mesh, const Edit& edit, const DeformOptions& options)
    : edit_(edit),
      strategy_(parse_frame_strategy(options.lri_frames)),
      ortho_(parse_orthonormalization(options.lri_orthonormalize)) {
  if (options.build == Build::Dense)
    throw InputError("LRI: the dense build is not offered (use --build structured or naive)");
  norm_ = options.normalize ? Normalization::fit(mesh.V) : Normalization::identity();
  Vn_ = norm_.apply(mesh.V);

  Timer t;
  adj_ = vertex_adjacency(mesh);
  const auto kinds = classify(edit, options.constraints);
  // Both systems couple exactly the 1-ring, so one anchoring check covers both.
  check_every_component_anchored(adj_, kinds);
  unk_ = make_unknowns(kinds, options.soft_weight);
  if (options.memory_budget > 0) {
    const std::size_t predicted = predict_edge_system_bytes(adj_, unk_, 3, options.build) +
                                  predict_edge_system_bytes(adj_, unk_, 1, options.build);
    if (predicted > options.memory_budget)
      throw BudgetError(fmt::format("{} build of the LRI systems needs about {:.1f} MB, over the budget of {:.1f} MB",
                                    to_string(options.build), predicted / 1e6, options.memory_budget / 1e6));
  }
  const Points N = vertex_normals(Vn_, mesh.F);
  frames_ = compute_frames(Vn_, adj_, N, strategy_, options.lri_seed);
  forms_ = discrete_forms(Vn_, adj_, frames_.F);
  fsys_ = build_edge_system(adj_, unk_, 3, frame_blocks(frames_.F), options.build);
  psys_ = build_edge_system(adj_, unk_, 1, position_blocks(), options.build);
  times_.build = t.seconds();

  SolverOptions fo = options.solver_options, po = options.solver_options;
  fo.block_size = 3;  // (b1, b2, N) components of one vertex share their pattern
  po.block_size = 1;
  fsolver_ = make_solver(options.solver, fo);
  psolver_ = make_solver(options.solver, po);
  t.reset();
  fsolver_->analyze(fsys_.K);
  psolver_->analyze(psys_.K);
  times_.analyze = t.seconds();
  t.reset();
  fsolver_->factorize(fsys_.K);
  psolver_->factorize(psys_.K);
  times_.factorize = t.seconds();
  systems_.push_back(report("frames", fsys_, *fsolver_));
  systems_.push_back(report("positions", psys_, *psolver_));
}

Points LriDeformer::deform(const Mat4& handle_transform) {
  const int n = static_cast<int>(Vn_.rows()), nu = unk_.num_unknowns(), nh = unk_.num_hard();
  const Mat4 T = norm_.conjugate(handle_transform);
  // Frames only rotate: a scaling or shearing handle transform reaches the frames through its rotation part.
  const Mat3 Rh = nearest_rotation(T.topLeftCorner<3, 3>());
  const double w2 = unk_.soft_weight * unk_.soft_weight;
  auto is_handle = [&](int v) { return edit_.roles[v] == Role::Handle; };
  auto frame_target = [&](int v) -> Mat3 { return is_handle(v) ? Mat3(Rh * frames_.F[v]) : frames_.F[v]; };
  auto position_target = [&](int v) -> Vec3 {
    const Vec3 p = Vn_.row(v).transpose();
    return is_handle(v) ? apply(T, p) : p;
  };

  // 1. frames: rhs = -C x_h (+ W u); the frame energy has no constant target.
  Timer t;
  double rhs_s = 0, solve_s = 0;
  xhf_.resize(3 * static_cast<Eigen::Index>(nh), 3);
  for (int h = 0; h < nh; ++h) {
    const Mat3 Ft = frame_target(unk_.hard_vertices[h]);
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) xhf_(3 * h + k, c) = Ft(c, k);
  }
  rhsf_.setZero(3 * static_cast<Eigen::Index>(nu), 3);
  if (nh > 0) rhsf_.noalias() -= fsys_.C * xhf_;
  for (int v : unk_.soft_vertices) {
    const Mat3 Ft = frame_target(v);
    const int u = unk_.unknown_of[v];
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) rhsf_(3 * u + k, c) += w2 * Ft(c, k);
  }
  rhs_s += t.seconds();
  t.reset();
  fsolver_->solve(rhsf_, xf_);
  solve_s += t.seconds();
  if (!xf_.allFinite()) throw SolverError("LRI: the frame solve produced non-finite values");

  // 2. orthonormalize, then the position targets F'_i d_ij of every directed edge.
  t.reset();
  raw_.resize(n);
  solved_.resize(n);
  for (int v = 0; v < n; ++v) {
    const int u = unk_.unknown_of[v];
    if (u < 0) {
      raw_[v] = solved_[v] = frame_target(v);
      continue;
    }
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) raw_[v](c, k) = xf_(3 * u + k, c);
    solved_[v] = orthonormalize(raw_[v], ortho_, v);
  }
  tpos_.setZero(static_cast<Eigen::Index>(adj_.nbr.size()), 3);
  for (int i = 0; i < n; ++i)
    for (int s = adj_.off[i]; s < adj_.off[i + 1]; ++s) tpos_.row(s) = (solved_[i] * forms_[s]).transpose();
  xhp_.resize(nh, 3);
  for (int h = 0; h < nh; ++h) xhp_.row(h) = position_target(unk_.hard_vertices[h]).transpose();
  rhsp_.setZero(nu, 3);
  add_At_targets(adj_, unk_, 1, position_blocks(), tpos_, rhsp_);
  if (nh > 0) rhsp_.noalias() -= psys_.C * xhp_;
  for (int v : unk_.soft_vertices) rhsp_.row(unk_.unknown_of[v]) += w2 * position_target(v).transpose();
  rhs_s += t.seconds();

  // 3. positions.
  t.reset();
  psolver_->solve(rhsp_, xp_);
  solve_s += t.seconds();
  if (!xp_.allFinite()) throw SolverError("LRI: the position solve produced non-finite positions");

  t.reset();
  Points Vn(n, 3);
  for (int v = 0; v < n; ++v) {
    const int u = unk_.unknown_of[v];
    Vn.row(v) = u >= 0 ? xp_.row(u) : xhp_.row(unk_.hard_of[v]);
  }
  Points out = norm_.restore(Vn);
  times_.write = t.seconds();
  times_.rhs = rhs_s;
  times_.solve = solve_s;
  return out;
}

std::unique_ptr<Deformer> make_lri_deformer(const Mesh& mesh, const Edit& edit, const DeformOptions& options) {
  validate_edit(mesh, edit);
  return std::make_unique<LriDeformer>(mesh, edit, options);
}

}  // namespace db
