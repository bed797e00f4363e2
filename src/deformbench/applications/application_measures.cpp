#include "applications/application_measures.h"

#include "applications/seam_metrics.h"

namespace db {
namespace {

// What both applications share: the target patch's sizes, the LSE system and its phases, the seam before and
// after, and how far the result moved from the target.
void add_common(NamedValues& v, const DiskPatch& patch, const LseReport& lse, const Mesh& before, const Mesh& after) {
  const SeamAngles s0 = seam_angles(before, patch), s1 = seam_angles(after, patch);
  const double diag = bbox_diagonal(before.V);
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
                     {"max_displacement_rel", diag > 0 ? (after.V - before.V).rowwise().norm().maxCoeff() / diag : 0.0}});
}

}  // namespace

NamedValues coat_measures(const Coating& coating, const CoatedTarget& t, const Mesh& target, double total_s) {
  const LseReport& sm = coating.smoothing;
  NamedValues v = {{"source_patch_vertices", coating.patch.num_vertices()},
                   {"parameterize_s", coating.parameterize_s + t.parameterize_s},
                   {"smooth_s", sm.build_s + sm.analyze_s + sm.factorize_s + sm.solve_s},
                   {"map_s", t.map_s}};
  add_common(v, t.patch, t.solve, target, t.result);
  // core: the vertices whose detail error is measured (coat: the patch's interior)
  v.insert(v.end(), {{"total_s", total_s}, {"detail_scale", t.scale}, {"detail_error", t.detail_error},
                     {"core_vertices", static_cast<double>(t.patch.num_vertices() - t.patch.boundary.size())}});
  return v;
}

NamedValues transplant_measures(const Transplant& t, const Mesh& target, double total_s) {
  NamedValues v = {{"source_patch_vertices", t.source_patch.num_vertices()},
                   {"parameterize_s", t.parameterize_s},
                   {"smooth_s", 0.0},
                   {"map_s", t.map_s}};
  add_common(v, t.patch, t.solve, target, t.result);
  // core: the vertices with blend 1, whose detail error is measured
  v.insert(v.end(), {{"total_s", total_s}, {"detail_scale", t.scale}, {"detail_error", t.detail_error},
                     {"core_vertices", t.core_vertices}});
  return v;
}

}  // namespace db
