#include "applications/transplant.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "applications/disk_parameterization.h"
#include "applications/parameter_map.h"
#include "core/timer.h"

namespace db {
namespace {

// The similarity (rotation, uniform scale, translation) taking the mapped source boundary onto the region's.
Mat4 fit_boundary(const DiskPatch& region, const Points& mapped, double& scale) {
  const auto m = static_cast<Eigen::Index>(region.boundary.size());
  Eigen::Matrix3Xd src(3, m), dst(3, m);
  for (Eigen::Index k = 0; k < m; ++k) {
    src.col(k) = mapped.row(region.boundary[k]).transpose();
    dst.col(k) = region.mesh.V.row(region.boundary[k]).transpose();
  }
  const Mat4 T = Eigen::umeyama(src, dst, true);
  scale = T.topLeftCorner<3, 3>().col(0).norm();
  return T;
}

double smoothstep(double t) {
  t = std::clamp(t, 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

}  // namespace

Transplant transplant_patch(const Mesh& source, const std::vector<int>& source_region, const Mesh& target,
                            const std::vector<int>& target_region, const TransplantOptions& options) {
  Transplant out;
  out.source_patch = extract_disk_patch(source, source_region, "source");
  out.patch = extract_disk_patch(target, target_region, "target");
  const DiskPatch& p = out.patch;
  Timer t;
  const UV uv_s = tutte_parameterization(out.source_patch), uv = tutte_parameterization(p);
  out.parameterize_s = t.seconds();
  t.reset();
  const Faces& Fs = out.source_patch.mesh.F;
  const Points mapped = interpolate(locate_in_parameter_domain(uv_s, Fs, uv), Fs, out.source_patch.mesh.V);
  const Mat4 T = fit_boundary(p, mapped, out.scale);
  out.placed = ((mapped * T.topLeftCorner<3, 3>().transpose()).rowwise() + T.topRightCorner<3, 1>().transpose());
  out.blend.resize(static_cast<std::size_t>(p.num_vertices()));
  for (int l = 0; l < p.num_vertices(); ++l)
    out.blend[l] = p.on_boundary[l] ? 0.0 : smoothstep((1.0 - uv.row(l).norm()) / options.zone);
  const Adjacency patch_adj = vertex_adjacency(p.mesh);
  const Points delta_s = uniform_delta(Mesh{out.placed, p.mesh.F, ""}, patch_adj);
  out.map_s = t.seconds();

  const Adjacency adj = vertex_adjacency(target);
  Points delta = uniform_delta(target, adj);
  std::vector<Constraint> kinds(static_cast<std::size_t>(target.num_vertices()), Constraint::Hard);
  for (int l = 0; l < p.num_vertices(); ++l) {
    if (p.on_boundary[l]) continue;  // boundary rows reach outside the patch: the target's own
    delta.row(p.parent[l]) += out.blend[l] * (delta_s.row(l) - delta.row(p.parent[l]));
    kinds[p.parent[l]] = Constraint::Free;
  }
  out.result = target;
  out.result.V = solve_lse(target, kinds, 1.0, delta, target.V, &out.solve);

  const Points got = uniform_delta(out.result, adj);
  double err2 = 0, ref2 = 0;
  for (int l = 0; l < p.num_vertices(); ++l) {
    if (out.blend[l] < 1.0) continue;
    ++out.core_vertices;
    err2 += (got.row(p.parent[l]) - delta_s.row(l)).squaredNorm();
    ref2 += delta_s.row(l).squaredNorm();
  }
  out.detail_error = ref2 > 0 ? std::sqrt(err2 / ref2) : 0.0;
  return out;
}

}  // namespace db
