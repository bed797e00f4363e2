#include "methods/edit_system.h"

#include <fmt/format.h>

#include "core/timer.h"
#include "methods/deformer.h"
#include "methods/normalization.h"
#include "operators/energy_operator.h"
#include "operators/frames.h"
#include "operators/lri_rows.h"
#include "solvers/base/error.h"
#include "systems/lri_system.h"
#include "systems/normal_system.h"

namespace db {
namespace {

// Vertex coordinate c of index u (unknown, hard or soft) in the solver layout: LAP keeps x, y, z as three columns,
// TF interleaves them in one.
inline double& at(DenseMat& M, int block, int u, int c) { return block == 1 ? M(u, c) : M(3 * u + c, 0); }

// The edit's setup (the deformers' own) under the resolved options.
struct Setup : EditSetup {
  DeformOptions o;
};

Setup setup(const Mesh& mesh, const Edit& edit, const DeformOptions& options) {
  Setup s;
  s.o = resolve_options(options);
  check_deform_input(mesh, edit, s.o);
  static_cast<EditSetup&>(s) = setup_edit(mesh, edit, s.o, /*tf_anchoring=*/s.o.method == Method::Tf);
  return s;
}

EnergyKind energy_of(Method m) { return m == Method::Lap ? EnergyKind::Lap : EnergyKind::Tf; }

// Where vertex v goes at the end of the drag, normalized: a handle vertex by the transform (or its last target),
// any other constrained vertex stays.
Vec3 target(const Setup& s, const Edit& edit, int v) {
  const Vec3 q = s.Vn.row(v).transpose();
  if (edit.roles[v] != Role::Handle) return q;
  if (edit.targets.rows() == 0) return apply(s.norm.conjugate(edit.transform), q);
  const std::vector<int> handle = edit.vertices(Role::Handle);
  const Eigen::Index h = static_cast<Eigen::Index>(handle.size());
  const Eigen::Index k = std::lower_bound(handle.begin(), handle.end(), v) - handle.begin();
  const Points p = s.norm.apply(edit.targets.row(edit.targets.rows() - h + k));
  return p.row(0).transpose();
}

// x_h (b#hard x cols) and u (b#soft x cols) of the drag's end.
void constraint_values(const Setup& s, const Edit& edit, int block, DenseMat& xh, DenseMat& u) {
  const int cols = block == 1 ? 3 : 1;
  xh.setZero(block * s.unk.num_hard(), cols);
  u.setZero(block * static_cast<Eigen::Index>(s.unk.soft_vertices.size()), cols);
  for (int h = 0; h < s.unk.num_hard(); ++h) {
    const Vec3 q = target(s, edit, s.unk.hard_vertices[h]);
    for (int c = 0; c < 3; ++c) at(xh, block, h, c) = q(c);
  }
  for (std::size_t k = 0; k < s.unk.soft_vertices.size(); ++k) {
    const Vec3 q = target(s, edit, s.unk.soft_vertices[k]);
    for (int c = 0; c < 3; ++c) at(u, block, int(k), c) = q(c);
  }
}

// K x_u = g0 - C x_h + W u.
DenseMat drag_rhs(const Setup& s, const Edit& edit, const NormalSystem& sys) {
  DenseMat xh, u;
  constraint_values(s, edit, sys.block, xh, u);
  DenseMat rhs = sys.g0;
  if (xh.rows() > 0) rhs -= sys.C * xh;
  const double w2 = s.unk.soft_weight * s.unk.soft_weight;
  for (std::size_t k = 0; k < s.unk.soft_vertices.size(); ++k) {
    const int x = s.unk.unknown_of[s.unk.soft_vertices[k]];
    for (int c = 0; c < sys.block; ++c) rhs.row(sys.block * x + c) += w2 * u.row(sys.block * int(k) + c);
  }
  return rhs;
}

EnergyOperator energy(const Setup& s, const Mesh& mesh) {
  EnergyOptions eo;
  eo.weights = s.o.weights;
  eo.tf_translation = s.o.tf_translation;
  return EnergyOperator(s.Vn, mesh.F, s.adj, energy_of(s.o.method), eo);
}

}  // namespace

std::vector<EditSystem> edit_systems(const Mesh& mesh, const Edit& edit, const DeformOptions& options) {
  const Setup s = setup(mesh, edit, options);
  Timer t;
  if (s.o.method != Method::Lri) {
    NormalSystem sys = build_normal_system(energy(s, mesh), s.unk, Build::Structured);
    EditSystem e{to_string(s.o.method), sys.block, {}, drag_rhs(s, edit, sys), 0};
    e.K.swap(sys.K);
    e.build_s = t.seconds();
    return {std::move(e)};
  }
  const FrameField frames =
      compute_frames(s.Vn, s.adj, vertex_normals(s.Vn, mesh.F), s.o.lri_frames, s.o.lri_seed);
  std::vector<EditSystem> v;
  NormalSystem f = build_edge_system(s.adj, s.unk, lri_frame_rows(frames.F), Build::Structured);
  v.push_back({"lri-frames", 3, {}, {}, 0});
  v.back().K.swap(f.K);
  v.back().build_s = t.seconds();
  t.reset();
  NormalSystem p = build_edge_system(s.adj, s.unk, lri_position_rows(), Build::Structured);
  v.push_back({"lri-positions", 1, {}, {}, 0});
  v.back().K.swap(p.K);
  v.back().build_s = t.seconds();
  return v;
}

LeastSquaresSystem edit_least_squares(const Mesh& mesh, const Edit& edit, const DeformOptions& options) {
  if (options.method == Method::Lri)
    throw UsageError("--least-squares: lap and tf only (lri's two systems are solved one after the other)");
  const Setup s = setup(mesh, edit, options);
  const NormalSystem sys = build_normal_system(energy(s, mesh), s.unk, Build::Naive);
  DenseMat xh, u;
  constraint_values(s, edit, sys.block, xh, u);
  return least_squares_system(sys, s.unk, xh, u);
}

}  // namespace db
