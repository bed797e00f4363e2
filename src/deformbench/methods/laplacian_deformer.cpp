#include "methods/laplacian_deformer.h"

#include <algorithm>
#include <functional>

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "solvers/base/resources.h"
#include "core/timer.h"
#include "solvers/mumps_mpi.h"
#include "systems/vertex_ordering.h"

namespace db {
namespace {
// Vertex coordinate c of unknown (or hard, or soft) index u in the solver layout: LAP keeps x, y, z as three
// right-hand-side columns; TF interleaves them in one column.
inline double& at(DenseMat& M, int block, int u, int c) { return block == 1 ? M(u, c) : M(3 * u + c, 0); }
inline double at(const DenseMat& M, int block, int u, int c) { return block == 1 ? M(u, c) : M(3 * u + c, 0); }
inline int op_block(EnergyKind k) { return k == EnergyKind::Lap ? 1 : 3; }
}  // namespace

LaplacianDeformer::LaplacianDeformer(const Mesh& mesh, const Edit& edit, EnergyKind kind,
                                     const DeformOptions& options)
    : edit_(edit), handle_vertices_(edit.vertices(Role::Handle)), handle_index_(edit.roles.size(), -1),
      handle_limit_(options.handle_limit) {
  for (std::size_t k = 0; k < handle_vertices_.size(); ++k) handle_index_[handle_vertices_[k]] = static_cast<int>(k);
  const std::string& solver = options.solver;  // resolved by make_deformer (resolve_options)
  setup_ = setup_edit(mesh, edit, options, /*tf_anchoring=*/kind == EnergyKind::Tf);
  times_.build = setup_.seconds;

  SolverOptions so = options.solver_options;
  so.block_size = op_block(kind);
  // The constraints pin the energy's null space (checked above), so the system is regular; the pivot bound for
  // singular input (10 n eps) would reject it at millions of unknowns, where TF's smallest pivot falls below
  // that bound. The smallest pivot is still reported.
  so.pivot_singularity_test = false;
  Timer t;
  EnergyOptions eo;
  eo.weights = options.weights;
  eo.tf_translation = options.tf_translation;
  const EnergyOperator op(setup_.Vn, mesh.F, setup_.adj, kind, eo);
  times_.build += t.seconds();

  std::string vertex_ordering;
  double ordering_seconds = 0;
  NormalSystem sys = build(op, options, solver, so, vertex_ordering, ordering_seconds);
  // Frames need only C and g0: the factor replaces K.
  mqwf_.precompute(std::move(sys), setup_.unk, to_string(kind), solver, so, /*consume_matrix=*/true);
  times_.analyze = ordering_seconds + mqwf_.analyze_seconds();
  times_.factorize = mqwf_.factorize_seconds();
  if (!vertex_ordering.empty()) mqwf_.report().factor.ordering_used = vertex_ordering + "-vertex-graph";
  normalize_scale_ = options.tf_scale == TfScale::Normalized;
  if (options.frame_mode == FrameMode::Handle) precompute_handle_frames();
  if (frame_mode_ == FrameMode::Full) set_varying();
  systems_.push_back(mqwf_.report());
  if (normalize_scale_) precompute_rescale(mesh.F, options, so);
}

void LaplacianDeformer::precompute_rescale(const Faces& F, const DeformOptions& options, const SolverOptions& so) {
  Timer t;
  EnergyOptions eo;
  eo.weights = options.weights;
  eo.tf_translation = options.tf_translation;
  lap_op_ = std::make_unique<EnergyOperator>(setup_.Vn, F, setup_.adj, EnergyKind::Lap, eo);
  // The unknowns keep TF's numbering (a vertex-graph order when the structured build ordered them; `so` then says
  // "natural"). The naive build's kept A^T cannot take the per-frame targets: the structured build, same K.
  const Build build = options.build == Build::Naive ? Build::Structured : options.build;
  const Unknowns& unk = setup_.unk;
  NormalSystem sys = rank_local(options) ? build_structured_share(*lap_op_, unk, options.rank, options.ranks,
                                                                  options.memory_budget)
                                         : build_normal_system(*lap_op_, unk, build, options.memory_budget);
  times_.build += t.seconds();
  SolverOptions lap_so = so;
  lap_so.block_size = 1;
  rescale_.precompute(std::move(sys), setup_.unk, "lap (tf scale pass)", options.solver,
                      lap_so, /*consume_matrix=*/true);
  times_.analyze += rescale_.analyze_seconds();
  times_.factorize += rescale_.factorize_seconds();
  systems_.push_back(rescale_.report());
}

Points LaplacianDeformer::rescale(const Points& Vn1) {
  // The linear term A_u^T (R delta) in LAP's layout: the targets R_i delta_i of the rows of L that reach an
  // unknown (a row among fixed vertices only adds nothing).
  const Points& delta = lap_op_->delta();
  const auto linear = [&](DenseMat& g) {
    std::vector<int> cols;
    std::vector<double> coeffs;
    for (int i = 0; i < delta.rows(); ++i) {
      lap_op_->row(i, cols, coeffs);
      if (std::none_of(cols.begin(), cols.end(), [&](int k) { return setup_.unk.unknown_of[k] >= 0; })) continue;
      const Eigen::RowVector3d target = (lap_op_->fitted_rotation(i, Vn1) * delta.row(i).transpose()).transpose();
      for (std::size_t k = 0; k < cols.size(); ++k)
        if (const int u = setup_.unk.unknown_of[cols[k]]; u >= 0) g.row(u) += coeffs[k] * target;
    }
  };
  // The constraint values of the first pass, in LAP's layout (one row per vertex, x y z columns).
  const auto scalar_layout = [](const DenseMat& M) {
    DenseMat out(M.rows() / 3, 3);
    for (Eigen::Index k = 0; k < out.rows(); ++k)
      for (int c = 0; c < 3; ++c) out(k, c) = M(3 * k + c, 0);
    return out;
  };
  DenseMat xh = scalar_layout(xh_), x;
  rescale_.form_rhs(xh, scalar_layout(soft_), linear);
  rescale_.solve(x);
  if (!x.allFinite()) throw SolverError("the scale pass produced non-finite positions");
  return positions(x, xh, 1);
}

Points LaplacianDeformer::positions(const DenseMat& x, const DenseMat& xh, int block) const {
  Points Vn(setup_.Vn.rows(), 3);
  for (int v = 0; v < Vn.rows(); ++v) {
    const int u = setup_.unk.unknown_of[v];
    for (int c = 0; c < 3; ++c) Vn(v, c) = u >= 0 ? at(x, block, u, c) : at(xh, block, setup_.unk.hard_of[v], c);
  }
  return Vn;
}

NormalSystem LaplacianDeformer::build(const EnergyOperator& op, const DeformOptions& options,
                                      const std::string& solver, SolverOptions& so, std::string& vertex_ordering,
                                      double& ordering_seconds) {
  // Structured builds number the unknowns in a fill-reducing order of the vertex graph (counted as analysis)
  // and hand the solver an already ordered matrix; the other builds, and backends that order nothing
  // (iterative ones), leave ordering to the solver, as the straightforward code would.
  const auto& accepted = solver_info(solver).orderings;
  const bool takes_natural = std::find(accepted.begin(), accepted.end(), "natural") != accepted.end();
  if (options.build == Build::Structured && so.ordering != "natural" && takes_natural)
    vertex_ordering = so.ordering == "default" ? default_vertex_ordering(so.block_size) : so.ordering;
  if (!vertex_ordering.empty()) so.ordering = "natural";
  NormalSystem sys;
  Timer t;
  if (rank_local(options)) return build_share(op, options, vertex_ordering, ordering_seconds);
  if (vertex_ordering == "amd" && worker_threads() > 1) {
    // AMD runs on one core: the build takes the other meanwhile (METIS uses both cores itself). Of the wall
    // time, the ordering thread's own counts as analysis, the rest as build.
    sys = build_structured_while_ordering(op, setup_.unk, vertex_ordering, options.memory_budget, ordering_seconds);
    times_.build += std::max(0.0, t.seconds() - ordering_seconds);
    return sys;
  }
  if (!vertex_ordering.empty()) {
    order_unknowns(op.adjacency(), setup_.unk, vertex_ordering);
    ordering_seconds = t.seconds();
  }
  t.reset();
  sys = build_normal_system(op, setup_.unk, options.build, options.memory_budget);
  times_.build += t.seconds();
  return sys;
}

bool LaplacianDeformer::rank_local(const DeformOptions& options) {
  return options.ranks > 1 && options.build == Build::Structured;
}

NormalSystem LaplacianDeformer::build_share(const EnergyOperator& op, const DeformOptions& options,
                                            const std::string& vertex_ordering, double& ordering_seconds) {
  Timer t;
  if (!vertex_ordering.empty()) {
    order_unknowns(op.adjacency(), setup_.unk, vertex_ordering);
    ordering_seconds = t.seconds();
  }
  // The shares are sums over one numbering of the unknowns: a rank that ordered differently would mix two.
  if (!mpi::same_on_every_rank(setup_.unk.unknown_vertices.data(), setup_.unk.unknown_vertices.size()))
    throw SolverError("rank-local assembly: the ranks numbered the unknowns differently (each rank must read the same "
                      "input and order it alike)");
  t.reset();
  NormalSystem sys = build_structured_share(op, setup_.unk, options.rank, options.ranks, options.memory_budget);
  times_.build += t.seconds();
  return sys;
}

void LaplacianDeformer::set_varying() {
  std::vector<int> hard, unknowns;
  for (int v : setup_.unk.soft_vertices)
    if (edit_.roles[v] == Role::Handle) unknowns.push_back(setup_.unk.unknown_of[v]);
  for (int h = 0; h < setup_.unk.num_hard(); ++h)
    if (edit_.roles[setup_.unk.hard_vertices[h]] == Role::Handle) hard.push_back(h);
  mqwf_.set_varying(hard, unknowns);
}

void LaplacianDeformer::constraint_values(const Mat4& T, const Points* targets) {
  const int b = mqwf_.system().block, r = mqwf_.system().rhs_cols;
  auto fill = [&](const std::vector<int>& vertices, DenseMat& M) {
    M.resize(static_cast<Eigen::Index>(b) * static_cast<Eigen::Index>(vertices.size()), r);
    for (std::size_t k = 0; k < vertices.size(); ++k) {
      const int v = vertices[k];
      const Vec3 p = setup_.Vn.row(v).transpose();
      Vec3 target = p;
      if (edit_.roles[v] == Role::Handle)
        target = targets ? Vec3(targets->row(handle_index_[v]).transpose()) : apply(T, p);
      for (int c = 0; c < 3; ++c) at(M, b, static_cast<int>(k), c) = target(c);
    }
  };
  fill(setup_.unk.hard_vertices, xh_);
  fill(setup_.unk.soft_vertices, soft_);
}

bool LaplacianDeformer::within_handle_limit(int m) {
  const int b = mqwf_.system().block;
  const double rows = static_cast<double>(b) * static_cast<double>(setup_.Vn.rows());
  const double bytes = rows * (m + (b == 1 ? 3 : 1)) * sizeof(double);
  const double factor = static_cast<double>(mqwf_.report().factor.factor_bytes);
  if (factor > 0 && bytes <= handle_limit_ * factor) return true;
  frame_mode_note_ = fmt::format(
      "handle mode: the responses to {} per-vertex targets would be {:.3g} MB, {:.2f} times the factor's {:.3g} MB, "
      "above the handle limit {:g} (--handle-limit): a frame streaming them would not beat a solve; full frames "
      "instead",
      handle_vertices_.size(), bytes / 1e6, factor > 0 ? bytes / factor : 0.0, factor / 1e6, handle_limit_);
  return false;
}

void LaplacianDeformer::precompute_handle_frames() {
  if (normalize_scale_)
    throw InputError("handle-mode frames: TF with normalized scale is not affine in the handle map (its second "
                     "pass rotates by the fitted rotations); use full frames");
  const int b = mqwf_.system().block;
  const bool drag = edit_.targets.rows() > 0;
  // Affine map: parameter 4c + j is entry (c, j) of its top 3 x 4 (LAP: j, shared by x, y, z). Per-vertex drag:
  // parameter b k + c is coordinate c of handle vertex k's displacement (LAP: k, shared likewise).
  const int m = drag ? b * static_cast<int>(handle_vertices_.size()) : b == 1 ? 4 : 12;
  if (drag && !within_handle_limit(m)) return;
  constraint_values(Mat4::Identity());
  // A handle vertex's target coordinate c is sum_j T(c, j) P_j with P = [p 1]: its basis column j (LAP; shared by
  // x, y, z) or 4c + j (TF, in the vertex's row c); under a drag, its own displacement: column b k + c.
  auto basis = [&](const std::vector<int>& vertices, DenseMat& M) {
    M.setZero(static_cast<Eigen::Index>(b) * static_cast<Eigen::Index>(vertices.size()), m);
    for (std::size_t k = 0; k < vertices.size(); ++k) {
      const int v = vertices[k];
      if (edit_.roles[v] != Role::Handle) continue;
      const Eigen::Index row = b * static_cast<Eigen::Index>(k);
      if (drag) {
        for (int c = 0; c < b; ++c) M(row + c, b * handle_index_[v] + c) = 1.0;
        continue;
      }
      const Eigen::Vector4d P(setup_.Vn(v, 0), setup_.Vn(v, 1), setup_.Vn(v, 2), 1.0);
      for (int c = 0; c < b; ++c)
        for (int j = 0; j < 4; ++j) M(row + c, b == 1 ? j : 4 * c + j) = P(j);
    }
  };
  DenseMat xh_basis, soft_basis;
  basis(setup_.unk.hard_vertices, xh_basis);
  basis(setup_.unk.soft_vertices, soft_basis);
  std::vector<int> source(setup_.Vn.rows() * b);  // output row b v + c: vertex v's coordinate c (LAP: its row)
  for (int v = 0; v < static_cast<int>(setup_.Vn.rows()); ++v)
    for (int c = 0; c < b; ++c)
      source[static_cast<std::size_t>(b * v + c)] = setup_.unk.unknown_of[v] >= 0
                                                        ? b * setup_.unk.unknown_of[v] + c
                                                        : -(b * setup_.unk.hard_of[v] + c) - 1;
  response_.precompute(mqwf_, xh_, soft_, xh_basis, soft_basis, source);
  response_.scale_and_shift(1.0 / setup_.norm.scale, setup_.norm.center);  // frames write restored positions
  times_.precompute = response_.seconds();
  response_bytes_ = response_.bytes();
  frame_mode_ = FrameMode::Handle;
}

Points LaplacianDeformer::stream(const DenseMat& theta) {
  Timer t;
  Points out(setup_.Vn.rows(), 3);
  if (!response_.evaluate(theta, out.data()))
    for (Eigen::Index v = 0; v < out.rows(); ++v)
      if (!out.row(v).allFinite())
        throw InputError(fmt::format("deformed vertex {}: a coordinate is beyond the largest double; scale the mesh "
                                     "down", v));
  times_.rhs = times_.solve = times_.write = 0;
  times_.response = t.seconds();
  return out;
}

Points LaplacianDeformer::deform_handle(const Mat4& handle_transform) {
  if (edit_.targets.rows() > 0) throw Error("handle-mode responses to per-vertex targets: frames are deform_targets");
  Timer t;
  const Mat4 D = setup_.norm.conjugate(handle_transform) - Mat4::Identity();
  const bool lap = mqwf_.system().block == 1;
  DenseMat theta(lap ? 4 : 12, lap ? 3 : 1);
  for (int c = 0; c < 3; ++c)
    for (int j = 0; j < 4; ++j) (lap ? theta(j, c) : theta(4 * c + j, 0)) = D(c, j);
  const double setup = t.seconds();
  Points out = stream(theta);
  times_.response += setup;
  return out;
}

Points LaplacianDeformer::deform_targets(const Points& targets) {
  const int h = static_cast<int>(handle_vertices_.size());
  if (targets.rows() != h || targets.cols() != 3 || !targets.allFinite())
    throw InputError(fmt::format("per-vertex targets: expected {} finite positions (one per handle vertex), got {}",
                                 h, targets.rows()));
  if (frame_mode_ == FrameMode::Full) return deform_full([&] {
    const Points tn = setup_.norm.apply(targets);
    constraint_values(Mat4::Identity(), &tn);
  });
  if (edit_.targets.rows() == 0) throw Error("handle-mode responses to the affine map: frames are deform");
  Timer t;
  const int b = mqwf_.system().block;
  DenseMat theta(b * h, b == 1 ? 3 : 1);  // each handle vertex's displacement, normalized
  for (int k = 0; k < h; ++k)
    for (int c = 0; c < 3; ++c) {
      const double d =
          (targets(k, c) - setup_.norm.center(c)) * setup_.norm.scale - setup_.Vn(handle_vertices_[k], c);
      (b == 1 ? theta(k, c) : theta(3 * k + c, 0)) = d;
    }
  const double setup = t.seconds();
  Points out = stream(theta);
  times_.response += setup;
  return out;
}

Points LaplacianDeformer::deform(const Mat4& handle_transform) {
  if (frame_mode_ == FrameMode::Handle) return deform_handle(handle_transform);
  return deform_full([&] { constraint_values(setup_.norm.conjugate(handle_transform)); });
}

Points LaplacianDeformer::deform_full(const std::function<void()>& set_values) {
  const int b = mqwf_.system().block;
  double base_seconds = 0;
  if (mqwf_.base_pending()) {
    // The rest pose's right-hand side, from which every frame differs only in the varying rows: the solver can
    // then redo just the part of the forward substitution those rows reach. Paid once, in the first frame's
    // solve.
    Timer tb;
    constraint_values(Mat4::Identity());
    mqwf_.set_base(xh_, soft_);
    base_seconds = tb.seconds();
  }
  Timer t;
  set_values();
  mqwf_.form_rhs(xh_, soft_);
  times_.rhs = t.seconds();

  t.reset();
  mqwf_.solve(x_);
  times_.solve = base_seconds + t.seconds();
  systems_.front().factor = mqwf_.report().factor;  // iterative and mixed backends: this solve's iterations
  if (!x_.allFinite()) throw SolverError("the solve produced non-finite positions");

  t.reset();
  Points Vn = positions(x_, xh_, b);
  double rescale_seconds = 0;
  if (lap_op_) {
    Timer tr;
    Vn = rescale(Vn);
    rescale_seconds = tr.seconds();
  }
  Points out = setup_.norm.restore(Vn);
  times_.solve += rescale_seconds;  // the second pass's right-hand side and solve
  times_.write = t.seconds() - rescale_seconds;
  return out;
}

}  // namespace db
