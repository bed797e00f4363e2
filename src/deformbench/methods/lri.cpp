#include "methods/lri.h"

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "core/timer.h"

namespace db {

LriDeformer::LriDeformer(const Mesh& mesh, const Edit& edit, const DeformOptions& options)
    : edit_(edit),
      strategy_(options.lri_frames),
      ortho_(options.lri_orthonormalize),
      uncoordinated_(options.lri_frame_control == FrameControl::Uncoordinated) {
  if (options.build == Build::Dense)
    throw InputError("LRI: the dense build is not offered (use --build structured or naive)");
  const std::string& solver = options.solver;  // resolved by make_deformer (resolve_options)
  // Both systems couple exactly the 1-ring, so one anchoring check covers both.
  setup_ = setup_edit(mesh, edit, options, /*tf_anchoring=*/false);
  Timer t;
  if (options.memory_budget > 0) {
    const std::size_t predicted = predict_edge_system_bytes(setup_.adj, setup_.unk, 3, options.build) +
                                  predict_edge_system_bytes(setup_.adj, setup_.unk, 1, options.build);
    if (predicted > options.memory_budget)
      throw BudgetError(fmt::format("{} build of the LRI systems needs about {:.1f} MB, over the budget of {:.1f} MB",
                                    to_string(options.build), predicted / 1e6, options.memory_budget / 1e6));
  }
  const Points N = vertex_normals(setup_.Vn, mesh.F);
  frames_ = compute_frames(setup_.Vn, setup_.adj, N, strategy_, options.lri_seed);
  forms_ = discrete_forms(setup_.Vn, setup_.adj, frames_.F);
  NormalSystem fsys = build_edge_system(setup_.adj, setup_.unk, lri_frame_rows(frames_.F), options.build);
  NormalSystem psys = build_edge_system(setup_.adj, setup_.unk, lri_position_rows(), options.build);
  times_.build = setup_.seconds + t.seconds();

  SolverOptions fo = options.solver_options, po = options.solver_options;
  fo.block_size = 3;  // (b1, b2, N) components of one vertex share their pattern
  po.block_size = 1;
  frames_mqwf_.analyze(std::move(fsys), setup_.unk, "frames", solver, fo);
  positions_mqwf_.analyze(std::move(psys), setup_.unk, "positions", solver, po);
  frames_mqwf_.factorize(/*consume_matrix=*/false);  // K is kept (frame_system())
  positions_mqwf_.factorize(/*consume_matrix=*/false);
  times_.analyze = frames_mqwf_.analyze_seconds() + positions_mqwf_.analyze_seconds();
  times_.factorize = frames_mqwf_.factorize_seconds() + positions_mqwf_.factorize_seconds();
  systems_.push_back(frames_mqwf_.report());
  systems_.push_back(positions_mqwf_.report());
  if (options.frame_mode == FrameMode::Handle) precompute_handle_frames();
}

void LriDeformer::precompute_handle_frames() {
  frame_rhs(Mat3::Identity());  // xhf_, softf_: the rest frames
  // A handle frame's target row c is row c of Rh F = sum_j Rh(c, j) F(j, :): basis column j holds row j of F.
  auto basis = [&](const std::vector<int>& vertices, DenseMat& M) {
    M.setZero(3 * static_cast<Eigen::Index>(vertices.size()), 3);
    for (std::size_t s = 0; s < vertices.size(); ++s) {
      const int v = vertices[s];
      if (edit_.roles[v] != Role::Handle) continue;
      for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j) M(3 * static_cast<Eigen::Index>(s) + k, j) = frames_.F[v](j, k);
    }
  };
  DenseMat xh_basis, soft_basis;
  basis(setup_.unk.hard_vertices, xh_basis);
  basis(setup_.unk.soft_vertices, soft_basis);
  std::vector<int> source(3 * setup_.Vn.rows());
  for (int v = 0; v < static_cast<int>(setup_.Vn.rows()); ++v)
    for (int k = 0; k < 3; ++k)
      source[static_cast<std::size_t>(3 * v + k)] =
          setup_.unk.unknown_of[v] >= 0 ? 3 * setup_.unk.unknown_of[v] + k : -(3 * setup_.unk.hard_of[v] + k) - 1;
  frame_response_.precompute(frames_mqwf_, xhf_, softf_, xh_basis, soft_basis, source);
  times_.precompute = frame_response_.seconds();
  response_bytes_ = frame_response_.bytes();
  xf_all_.resize(3 * setup_.Vn.rows(), 3);
  frame_mode_ = FrameMode::Handle;
}

void LriDeformer::solve_frames(const Mat3& Rh, double& rhs_s, double& solve_s) {
  if (frame_mode_ == FrameMode::Handle) {
    Timer t;
    DenseMat theta(3, 3);
    for (int c = 0; c < 3; ++c)
      for (int j = 0; j < 3; ++j) theta(j, c) = Rh(c, j) - (c == j ? 1.0 : 0.0);
    if (!frame_response_.evaluate(theta, xf_all_.data()))
      throw SolverError("LRI: the frame responses produced non-finite values");
    times_.response = t.seconds();
    rhs_s = solve_s = 0;
    return;
  }
  rhs_s = frame_rhs(Rh);
  Timer t;
  frames_mqwf_.solve(xf_);
  solve_s = t.seconds();
  systems_[0].factor = frames_mqwf_.report().factor;  // iterative and mixed backends: this solve's iterations
  if (!xf_.allFinite()) throw SolverError("LRI: the frame solve produced non-finite values");
}

double LriDeformer::frame_rhs(const Mat3& Rh) {
  // Per world component c the unknowns of vertex v are row c of its frame: rows 3k+.. hold column k.
  auto fill = [&](const std::vector<int>& vertices, DenseMat& M) {
    M.resize(3 * static_cast<Eigen::Index>(vertices.size()), 3);
    for (std::size_t s = 0; s < vertices.size(); ++s) {
      const int v = vertices[s];
      const Mat3 Ft = edit_.roles[v] == Role::Handle ? Mat3(Rh * frames_.F[v]) : frames_.F[v];
      for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 3; ++c) M(3 * static_cast<Eigen::Index>(s) + k, c) = Ft(c, k);
    }
  };
  Timer t;
  fill(setup_.unk.hard_vertices, xhf_);
  fill(setup_.unk.soft_vertices, softf_);
  frames_mqwf_.form_rhs(xhf_, softf_);  // the frame energy has no constant target
  return t.seconds();
}

double LriDeformer::position_rhs(const Mat4& T) {
  const int n = static_cast<int>(setup_.Vn.rows());
  Timer t;
  // Orthonormalize, then the position targets F'_i d_ij of every directed edge.
  raw_.resize(n);
  solved_.resize(n);
  const bool handle = frame_mode_ == FrameMode::Handle;
  for (int v = 0; v < n; ++v) {
    const int u = setup_.unk.unknown_of[v];
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c)
        raw_[v](c, k) = handle ? xf_all_(3 * v + k, c)
                        : u >= 0 ? xf_(3 * u + k, c)
                                 : xhf_(3 * setup_.unk.hard_of[v] + k, c);
    solved_[v] = u >= 0 ? orthonormalize(raw_[v], ortho_, v) : raw_[v];  // a hard frame is its target
  }
  times_.orthonormalize = t.seconds();
  lri_position_targets(setup_.adj, solved_, forms_, tpos_);
  auto fill = [&](const std::vector<int>& vertices, DenseMat& M) {
    M.resize(static_cast<Eigen::Index>(vertices.size()), 3);
    for (std::size_t s = 0; s < vertices.size(); ++s) {
      const int v = vertices[s];
      const Vec3 p = setup_.Vn.row(v).transpose();
      M.row(static_cast<Eigen::Index>(s)) = (edit_.roles[v] == Role::Handle ? apply(T, p) : p).transpose();
    }
  };
  fill(setup_.unk.hard_vertices, xhp_);
  fill(setup_.unk.soft_vertices, softp_);
  const EdgeRows rows = lri_position_rows();
  positions_mqwf_.form_rhs(xhp_, softp_, [&](DenseMat& g) { add_At_targets(setup_.adj, setup_.unk, rows, tpos_, g); });
  return t.seconds();
}

Points LriDeformer::deform(const Mat4& handle_transform) {
  const Mat4 T = setup_.norm.conjugate(handle_transform);
  // Frames only rotate: a scaling or shearing handle transform reaches the frames through its rotation part.
  const Mat3 Rh = uncoordinated_ ? Mat3::Identity() : nearest_rotation(T.topLeftCorner<3, 3>());
  double rhs_s = 0, solve_s = 0;
  solve_frames(Rh, rhs_s, solve_s);
  rhs_s += position_rhs(T);
  Timer t;
  positions_mqwf_.solve(xp_);
  solve_s += t.seconds();
  systems_[1].factor = positions_mqwf_.report().factor;
  if (!xp_.allFinite()) throw SolverError("LRI: the position solve produced non-finite positions");

  t.reset();
  const int n = static_cast<int>(setup_.Vn.rows());
  Points Vn(n, 3);
  for (int v = 0; v < n; ++v) {
    const int u = setup_.unk.unknown_of[v];
    Vn.row(v) = u >= 0 ? xp_.row(u) : xhp_.row(setup_.unk.hard_of[v]);
  }
  Points out = setup_.norm.restore(Vn);
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
