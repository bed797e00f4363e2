#include "applications/application_measures.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

#include "applications/seam_metrics.h"
#include "operators/frames.h"

namespace db {
namespace {

int boundary_edges(const Mesh& m) {
  std::map<std::pair<int, int>, int> uses;
  for (int f = 0; f < m.num_faces(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int a = m.F(f, c), b = m.F(f, (c + 1) % 3);
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  int n = 0;
  for (const auto& [e, k] : uses) n += k == 1;
  return n;
}

// Whether the result is one sound surface: its non-manifold edges and vertices, degenerate faces, and the
// boundary edges it has beyond the target's (a seam left open; 0 when the join is closed).
void add_soundness(NamedValues& v, const Mesh& before, const Mesh& after) {
  const NonManifold nm = find_non_manifold(after);
  const double diag = bbox_diagonal(after.V);
  int degenerate = 0;
  for (int f = 0; f < after.num_faces(); ++f) degenerate += !degenerate_face(after, f, diag).empty();
  v.insert(v.end(), {{"result_vertices", after.num_vertices()},
                     {"result_faces", after.num_faces()},
                     {"nonmanifold", static_cast<double>(nm.edges.size() + nm.vertices.size())},
                     {"degenerate_faces", degenerate},
                     {"open_seam_edges", boundary_edges(after) - boundary_edges(before)}});
}

// What both applications share: the target patch's sizes, the LSE system and its phases, the seam before and
// after, and the largest move of the LSE solve from its start (relative to the target's diagonal).
void add_common(NamedValues& v, const DiskPatch& patch, const LseReport& lse, const Mesh& before,
                const SeamAngles& s0, const SeamAngles& s1, double moved) {
  v.insert(v.end(), {{"target_vertices", before.num_vertices()},
                     {"target_faces", before.num_faces()},
                     {"patch_vertices", patch.num_vertices()},
                     {"patch_faces", patch.mesh.num_faces()},
                     {"patch_boundary", static_cast<double>(patch.boundary.size())},
                     {"n", static_cast<double>(lse.system.n)},
                     {"nnz", static_cast<double>(lse.system.nnz)},
                     {"nnz_factor", static_cast<double>(lse.system.factor.nnz_factor)},
                     {"build_s", lse.build_s},
                     {"analyze_s", lse.analyze_s},
                     {"factorize_s", lse.factorize_s},
                     {"solve_s", lse.solve_s},
                     {"seam_edges", s1.edges},
                     {"seam_max_deg_before", s0.max_deg},
                     {"seam_max_deg_after", s1.max_deg},
                     {"seam_mean_deg_before", s0.mean_deg},
                     {"seam_mean_deg_after", s1.mean_deg},
                     {"max_displacement_rel", moved / bbox_diagonal(before.V)}});
}

// Largest |h| and the area-weighted root mean square of per-vertex heights h on the surface (V, F).
std::pair<double, double> height_max_rms(const Points& V, const Faces& F, const Eigen::VectorXd& h) {
  Eigen::VectorXd area = Eigen::VectorXd::Zero(V.rows());
  for (int f = 0; f < F.rows(); ++f) {
    const Vec3 a = V.row(F(f, 1)) - V.row(F(f, 0)), b = V.row(F(f, 2)) - V.row(F(f, 0));
    for (int c = 0; c < 3; ++c) area[F(f, c)] += a.cross(b).norm() / 6;
  }
  return {h.cwiseAbs().maxCoeff(), std::sqrt(area.dot(h.cwiseProduct(h)) / area.sum())};
}

// (X - Y) . n per row, n the unit vertex normals of (Y, F).
Eigen::VectorXd normal_heights(const Points& X, const Points& Y, const Faces& F) {
  const Points n = vertex_normals(Y, F);
  return (X - Y).cwiseProduct(n).rowwise().sum();
}

}  // namespace

CoatingAmplitude coating_amplitude(const Coating& coating, const CoatedTarget& t, const Mesh& target) {
  const Mesh& s = coating.patch.mesh;
  const auto [s_max, s_rms] = height_max_rms(coating.smooth, s.F, normal_heights(s.V, coating.smooth, s.F));
  Points before(t.patch.num_vertices(), 3), after(t.patch.num_vertices(), 3);
  for (int l = 0; l < t.patch.num_vertices(); ++l) {
    before.row(l) = target.V.row(t.patch.parent[l]);
    after.row(l) = t.result.V.row(t.patch.parent[l]);
  }
  const auto [t_max, t_rms] = height_max_rms(before, t.patch.mesh.F, normal_heights(after, before, t.patch.mesh.F));
  CoatingAmplitude a;
  a.max_ratio = s_max > 0 ? t_max / (t.sigma * s_max) : 0.0;
  a.rms_ratio = s_rms > 0 ? t_rms / (t.sigma * s_rms) : 0.0;
  return a;
}

NamedValues coat_measures(const Coating& coating, const CoatedTarget& t, const Mesh& target, double total_s) {
  const LseReport& sm = coating.smoothing;
  NamedValues v = {{"source_patch_vertices", coating.patch.num_vertices()},
                   {"parameterize_s", coating.parameterize_s + t.parameterize_s},
                   {"smooth_s", sm.build_s + sm.analyze_s + sm.factorize_s + sm.solve_s},
                   {"map_s", t.map_s}};
  add_common(v, t.patch, t.solve, target, seam_angles(target, t.patch), seam_angles(t.result, t.patch),
             (t.result.V - target.V).rowwise().norm().maxCoeff());
  add_soundness(v, target, t.result);
  // core: the vertices whose detail error is measured (coat: the patch's interior); coat joins nothing
  v.insert(v.end(), {{"band_faces", 0.0}, {"welded", 0.0}, {"band_by_diagonal", 0.0}, {"rho", 1.0}, {"total_s", total_s},
                     {"detail_scale", t.scale}, {"detail_error", t.detail_error},
                     {"core_vertices", static_cast<double>(t.patch.num_vertices() - t.patch.boundary.size())}});
  const CoatingAmplitude a = coating_amplitude(coating, t, target);
  v.insert(v.end(), {{"sigma", t.sigma}, {"height_max_ratio", a.max_ratio}, {"height_rms_ratio", a.rms_ratio}});
  return v;
}

NamedValues transplant_measures(const Transplant& t, const Mesh& target, double total_s) {
  NamedValues v = {{"source_patch_vertices", t.source_patch.num_vertices()},
                   {"parameterize_s", t.parameterize_s},
                   {"smooth_s", 0.0},
                   {"map_s", t.map_s}};
  add_common(v, t.patch, t.solve, target, t.seam_before, t.seam_after,
             (t.result.V - t.placed).rowwise().norm().maxCoeff());
  add_soundness(v, target, t.result);
  // core: the source vertices with blend 1, whose detail error is measured
  v.insert(v.end(), {{"band_faces", t.band_faces}, {"welded", t.welded ? 1.0 : 0.0},
                     {"band_by_diagonal", t.band_by_diagonal ? 1.0 : 0.0}, {"rho", t.rho},
                     {"total_s", total_s}, {"detail_scale", t.scale}, {"detail_error", t.detail_error},
                     {"core_vertices", t.core_vertices}});
  const double none = std::numeric_limits<double>::quiet_NaN();  // the coating's columns, so both rows match
  v.insert(v.end(), {{"sigma", none}, {"height_max_ratio", none}, {"height_rms_ratio", none}});
  return v;
}

}  // namespace db
