#include "applications/application_measures.h"

#include <algorithm>
#include <map>
#include <utility>

#include "applications/seam_metrics.h"

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

}  // namespace

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
  return v;
}

}  // namespace db
