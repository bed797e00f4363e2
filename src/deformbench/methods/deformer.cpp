#include "methods/deformer.h"

#include <cmath>
#include <iostream>

#include <fmt/format.h>

#include "core/timer.h"
#include "solvers/base/error.h"
#include "methods/laplacian_deformer.h"
#include "methods/lri.h"

namespace db {

namespace {
[[noreturn]] void refuse_targets() {
  throw InputError("per-vertex handle targets ('targets' in the edit) need --method lap or tf: lri's frames follow "
                   "one handle rotation, which per-vertex targets do not give (fitting one is not linear in them)");
}
}  // namespace

Points Deformer::deform_targets(const Points&) { refuse_targets(); }

std::size_t Deformer::matrix_bytes() const {
  std::size_t s = 0;
  for (const auto& r : systems_) s += r.matrix_bytes;
  return s;
}

std::size_t Deformer::factor_bytes() const {
  std::size_t s = 0;
  for (const auto& r : systems_) s += r.factor.factor_bytes;
  return s;
}

std::vector<Constraint> classify(const Edit& edit, ConstraintMode mode) {
  std::vector<Constraint> kind(edit.roles.size());
  for (std::size_t v = 0; v < kind.size(); ++v)
    kind[v] = edit.roles[v] == Role::Free ? Constraint::Free
              : mode == ConstraintMode::Hard ? Constraint::Hard
                                             : Constraint::Soft;
  return kind;
}

namespace {

//! Whether some three of the points are not on one line (to a relative 1e-6 of their extent).
bool spans_a_plane(const Points& V, const std::vector<int>& pts) {
  if (pts.size() < 3) return false;
  const Vec3 p0 = V.row(pts[0]).transpose();
  Vec3 d = Vec3::Zero();
  for (int v : pts)
    if ((V.row(v).transpose() - p0).squaredNorm() > d.squaredNorm()) d = V.row(v).transpose() - p0;
  if (d.squaredNorm() == 0) return false;
  for (int v : pts)
    if ((V.row(v).transpose() - p0).cross(d).norm() > 1e-6 * d.squaredNorm()) return true;
  return false;
}

// Uniform LAP and TF are defined on the vertex graph and deform a non-manifold mesh as it is (with a warning);
// cotan weights and LRI's frames need a manifold 1-ring around every vertex.
void check_manifold(const Mesh& mesh, const DeformOptions& options) {
  const NonManifold nm = find_non_manifold(mesh);
  if (nm.empty()) return;
  const std::string who = mesh.name.empty() ? std::string("mesh") : "mesh '" + mesh.name + "'";
  const bool lri = options.method == Method::Lri;
  if (lri || options.weights == Weights::Cotan)
    throw InputError(fmt::format("{} is not manifold: {}; {} needs a manifold 1-ring around every vertex. Run "
                                 "`meshtool repair IN OUT` to split them (uniform lap and tf take the mesh as it is)",
                                 who, nm.summary(),
                                 lri ? "lri" : to_string(options.method) + " with cotan weights"));
  std::cerr << fmt::format("warning: {} is not manifold: {}; {} with uniform weights works on the vertex graph and "
                           "deforms it as it is (`meshtool repair` splits them)\n",
                           who, nm.summary(), to_string(options.method));
}

}  // namespace

void check_every_component_anchored(const Adjacency& adj, const std::vector<Constraint>& kind,
                                    const Points* positions) {
  const int n = adj.num_vertices();
  std::vector<int> comp(n, -1), stack, pins;
  for (int s = 0; s < n; ++s) {
    if (comp[s] >= 0 || kind[s] == Constraint::Hard) continue;
    // Flood the unknowns reachable from s; the component is anchored when it holds a soft vertex or
    // borders a hard one.
    bool anchored = false;
    int size = 0;
    stack.assign(1, s);
    comp[s] = s;
    pins.clear();
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      ++size;
      if (kind[v] == Constraint::Soft) {
        anchored = true;
        pins.push_back(v);
      }
      for (const int* p = adj.begin(v); p != adj.end(v); ++p) {
        if (kind[*p] == Constraint::Hard) {
          anchored = true;
          pins.push_back(*p);
        } else if (comp[*p] < 0) {
          comp[*p] = s;
          stack.push_back(*p);
        }
      }
    }
    if (!anchored)
      throw InputError(fmt::format(
          "singular system: {} free vertices (component containing vertex {}) touch no fixed vertex, handle or "
          "soft anchor",
          size, s));
    if (positions && !spans_a_plane(*positions, pins))
      throw InputError(fmt::format(
          "singular system: {} free vertices (component containing vertex {}) are held by constrained vertices "
          "that all lie on one line; TF needs three not on one line, or the component can rotate about that line "
          "at no cost",
          size, s));
  }
}

void check_deform_input(const Mesh& mesh, const Edit& edit, const DeformOptions& options) {
  // Cheap next to any build; library callers may not have loaded through edit_io.
  validate_mesh(mesh, Manifold::Allowed);
  validate_edit(mesh, edit);
  check_manifold(mesh, options);
}

std::unique_ptr<Deformer> make_deformer(const Mesh& mesh, const Edit& edit, const DeformOptions& options) {
  const DeformOptions o = resolve_options(options);  // the same check as the command line's, and the backend named
  check_deform_input(mesh, edit, o);
  switch (o.method) {
    case Method::Lap: return std::make_unique<LaplacianDeformer>(mesh, edit, EnergyKind::Lap, o);
    case Method::Tf: return std::make_unique<LaplacianDeformer>(mesh, edit, EnergyKind::Tf, o);
    case Method::Lri:
      if (edit.targets.rows() > 0) refuse_targets();
      return make_lri_deformer(mesh, edit, o);
  }
  throw Error("make_deformer: a method outside the table");
}

EditSetup setup_edit(const Mesh& mesh, const Edit& edit, const DeformOptions& options, bool tf_anchoring) {
  EditSetup s;
  s.norm = options.normalize ? Normalization::fit(mesh.V) : Normalization::identity();
  s.Vn = s.norm.apply(mesh.V);
  Timer t;
  s.adj = vertex_adjacency(mesh);
  const auto kinds = classify(edit, options.constraints);
  check_every_component_anchored(s.adj, kinds, tf_anchoring ? &s.Vn : nullptr);
  s.unk = make_unknowns(kinds, options.soft_weight);
  s.seconds = t.seconds();
  return s;
}

}  // namespace db
