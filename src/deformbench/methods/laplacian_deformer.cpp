#include "methods/laplacian_deformer.h"

#include <algorithm>

#include <fmt/format.h>

#include "core/error.h"
#include "core/resources.h"
#include "core/timer.h"
#include "systems/vertex_ordering.h"

namespace db {
namespace {
// Vertex coordinate c of unknown (or hard) index u in the solver layout: LAP keeps x, y, z as three
// right-hand-side columns; TF interleaves them in one column.
inline double& at(DenseMat& M, int block, int u, int c) { return block == 1 ? M(u, c) : M(3 * u + c, 0); }
inline int op_block(EnergyKind k) { return k == EnergyKind::Lap ? 1 : 3; }
}  // namespace

LaplacianDeformer::LaplacianDeformer(const Mesh& mesh, const Edit& edit, EnergyKind kind,
                                     const DeformOptions& options)
    : edit_(edit) {
  norm_ = options.normalize ? Normalization::fit(mesh.V) : Normalization::identity();
  Vn_ = norm_.apply(mesh.V);
  Timer t;
  const Adjacency adj = vertex_adjacency(mesh);
  const auto kinds = classify(edit, options.constraints);
  check_every_component_anchored(adj, kinds, kind == EnergyKind::Tf ? &Vn_ : nullptr);
  unk_ = make_unknowns(kinds, options.soft_weight);
  times_.build = t.seconds();

  // Structured builds number the unknowns in a fill-reducing order of the vertex graph (counted as analysis)
  // and hand the solver an already ordered matrix; the other builds, and backends that order nothing
  // (iterative ones), leave ordering to the solver, as the straightforward code would.
  SolverOptions so = options.solver_options;
  so.block_size = op_block(kind);
  // The constraints pin the energy's null space (checked above), so the system is regular; the pivot bound for
  // singular input (10 n eps) would reject it at millions of unknowns, where TF's smallest pivot falls below
  // that bound (armadillo Loop 3: 4.5e-9 against 1.1e-8). The smallest pivot is still reported.
  so.pivot_singularity_test = false;
  t.reset();
  EnergyOptions eo;
  eo.weights = options.weights;
  eo.tf_translation = options.tf_translation;
  const EnergyOperator op(Vn_, mesh.F, adj, kind, eo);
  times_.build += t.seconds();

  std::string vertex_ordering;
  const auto& accepted = solver_info(options.solver).orderings;
  const bool takes_natural = std::find(accepted.begin(), accepted.end(), "natural") != accepted.end();
  if (options.build == Build::Structured && so.ordering != "natural" && takes_natural)
    vertex_ordering = so.ordering == "default" ? default_vertex_ordering(so.block_size) : so.ordering;
  double ordering_seconds = 0;
  t.reset();
  if (vertex_ordering == "amd" && worker_threads() > 1) {
    // AMD runs on one core: the build takes the other meanwhile (METIS uses both cores itself). Of the wall
    // time, the ordering thread's own counts as analysis, the rest as build.
    sys_ = build_structured_while_ordering(op, unk_, vertex_ordering, options.memory_budget, ordering_seconds);
    times_.build += std::max(0.0, t.seconds() - ordering_seconds);
  } else {
    if (!vertex_ordering.empty()) order_unknowns(adj, unk_, vertex_ordering);
    ordering_seconds = t.seconds();
    t.reset();
    sys_ = build_normal_system(op, unk_, options.build, options.memory_budget);
    times_.build += t.seconds();
  }
  if (!vertex_ordering.empty()) so.ordering = "natural";

  SystemReport rep;
  rep.name = to_string(kind);
  rep.n = sys_.n();
  rep.held_bytes = sys_.held_bytes;
  if (options.build == Build::Dense) {
    rep.nnz = static_cast<std::size_t>(sys_.K_dense.size());
    rep.matrix_bytes = rep.nnz * sizeof(double);
    t.reset();
    llt_ = std::make_unique<Eigen::LLT<DenseMat>>(sys_.K_dense);
    times_.factorize = t.seconds();
    if (llt_->info() != Eigen::Success)
      throw SolverError(fmt::format("dense Cholesky: the {} system ({} unknowns) is not positive definite",
                                    to_string(kind), sys_.n()));
    rep.factor.n = sys_.n();
    rep.factor.nnz_factor = sys_.n() * (sys_.n() + 1) / 2;
    rep.factor.factor_bytes = static_cast<std::size_t>(sys_.K_dense.size()) * sizeof(double);
    rep.factor.flops = static_cast<double>(sys_.n()) * sys_.n() * sys_.n() / 3.0;
    rep.factor.ordering_used = "none";
  } else {
    rep.nnz = static_cast<std::size_t>(sys_.K.nonZeros());
    rep.matrix_bytes = sparse_bytes(sys_.K);
    solver_ = make_solver(options.solver, so);
    t.reset();
    solver_->analyze(sys_.K);
    times_.analyze = ordering_seconds + t.seconds();
    t.reset();
    solver_->factorize_consuming(sys_.K);  // frames need only C and g0; the factor replaces K
    times_.factorize = t.seconds();
    rep.factor = solver_->stats();
    if (!vertex_ordering.empty()) rep.factor.ordering_used = vertex_ordering + "-vertex-graph";
    frame_rows_ = handle_rows();
  }
  systems_.push_back(std::move(rep));
}

std::vector<int> LaplacianDeformer::handle_rows() const {
  const int b = sys_.block;
  std::vector<char> changes(static_cast<std::size_t>(sys_.n()), 0);
  for (int v : unk_.soft_vertices)
    if (edit_.roles[v] == Role::Handle)
      for (int c = 0; c < b; ++c) changes[static_cast<std::size_t>(b * unk_.unknown_of[v] + c)] = 1;
  for (int h = 0; h < unk_.num_hard(); ++h)
    if (edit_.roles[unk_.hard_vertices[h]] == Role::Handle)
      for (int c = 0; c < b; ++c)
        for (SpMat::InnerIterator it(sys_.C, b * h + c); it; ++it) changes[static_cast<std::size_t>(it.row())] = 1;
  std::vector<int> rows;
  for (std::size_t i = 0; i < changes.size(); ++i)
    if (changes[i]) rows.push_back(static_cast<int>(i));
  return rows;
}

void LaplacianDeformer::assemble_rhs(const Mat4& T) {
  const int b = sys_.block, r = sys_.rhs_cols;
  auto target = [&](int v) -> Vec3 {
    const Vec3 p = Vn_.row(v).transpose();
    return edit_.roles[v] == Role::Handle ? apply(T, p) : p;
  };
  xh_.resize(static_cast<Eigen::Index>(b) * unk_.num_hard(), r);
  for (int h = 0; h < unk_.num_hard(); ++h) {
    const Vec3 p = target(unk_.hard_vertices[h]);
    for (int c = 0; c < 3; ++c) at(xh_, b, h, c) = p(c);
  }
  if (sys_.build == Build::Naive) {  // the thesis' first version: A^T (b - A_h x_h), a product with A^T per frame
    if (unk_.num_hard() > 0) rhs_.noalias() = sys_.At * DenseMat(sys_.targets - sys_.Ah * xh_);
    else rhs_.noalias() = sys_.At * sys_.targets;
  } else {
    rhs_ = sys_.g0;
    if (unk_.num_hard() > 0) {
      if (sys_.build == Build::Dense) rhs_.noalias() -= sys_.C_dense * xh_;
      else rhs_.noalias() -= sys_.C * xh_;
    }
  }
  const double w2 = unk_.soft_weight * unk_.soft_weight;
  for (int v : unk_.soft_vertices) {
    const Vec3 p = target(v);
    for (int c = 0; c < 3; ++c) at(rhs_, b, unk_.unknown_of[v], c) += w2 * p(c);
  }
}

Points LaplacianDeformer::deform(const Mat4& handle_transform) {
  const int b = sys_.block;
  double base_seconds = 0;
  if (solver_ && !base_rhs_set_) {
    // The rest pose's right-hand side, from which every frame differs only in frame_rows_: the solver can then
    // redo just the part of the forward substitution those rows reach. Paid once, in the first frame's solve.
    Timer tb;
    assemble_rhs(Mat4::Identity());
    solver_->set_base_rhs(rhs_, frame_rows_);
    base_rhs_set_ = true;
    base_seconds = tb.seconds();
  }
  Timer t;
  assemble_rhs(norm_.conjugate(handle_transform));
  times_.rhs = t.seconds();

  t.reset();
  if (llt_) x_ = llt_->solve(rhs_);
  else solver_->solve_changed(rhs_, x_);
  times_.solve = base_seconds + t.seconds();
  if (!x_.allFinite()) throw SolverError("the solve produced non-finite positions");

  t.reset();
  Points Vn(Vn_.rows(), 3);
  for (int v = 0; v < Vn.rows(); ++v) {
    const int u = unk_.unknown_of[v];
    for (int c = 0; c < 3; ++c) Vn(v, c) = u >= 0 ? at(x_, b, u, c) : at(xh_, b, unk_.hard_of[v], c);
  }
  Points out = norm_.restore(Vn);
  times_.write = t.seconds();
  return out;
}

}  // namespace db
