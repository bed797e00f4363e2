#include "applications/transplant.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include "applications/disk_parameterization.h"
#include "applications/parameter_map.h"
#include "applications/zipper.h"
#include "solvers/base/error.h"
#include "core/timer.h"
#include "operators/frames.h"

namespace db {
namespace {

// The point of patch p's surface at each parameter point of `query`.
Points surface_at(const DiskPatch& p, const UV& uv, const UV& query) {
  return interpolate(locate_in_parameter_domain(uv, p.mesh.F, query), p.mesh.F, p.mesh.V);
}

// The similarity (rotation, uniform scale, translation) taking the source boundary onto `to` (its rows for the
// source's boundary vertices), applied to the whole source patch.
Points place_source(const DiskPatch& s, const Points& to, double& scale) {
  const auto m = static_cast<Eigen::Index>(s.boundary.size());
  Eigen::Matrix3Xd src(3, m), dst(3, m);
  for (Eigen::Index k = 0; k < m; ++k) {
    src.col(k) = s.mesh.V.row(s.boundary[k]).transpose();
    dst.col(k) = to.row(s.boundary[k]).transpose();
  }
  const Mat4 T = Eigen::umeyama(src, dst, true);
  scale = T.topLeftCorner<3, 3>().col(0).norm();
  return (s.mesh.V * T.topLeftCorner<3, 3>().transpose()).rowwise() + T.topRightCorner<3, 1>().transpose();
}

// The mean parameter radius of the region's first inner ring: where the source's boundary goes, so the band
// between the two loops is about one ring of the target wide.
double inner_ring_radius(const DiskPatch& p, const UV& uv) {
  const Adjacency adj = vertex_adjacency(p.mesh);
  double sum = 0;
  int count = 0;
  for (int v = 0; v < p.num_vertices(); ++v) {
    if (p.on_boundary[v]) continue;
    if (std::any_of(adj.begin(v), adj.end(v), [&](int q) { return p.on_boundary[q] != 0; })) {
      sum += uv.row(v).norm();
      ++count;
    }
  }
  return std::clamp(count > 0 ? sum / count : 0.5, 0.5, 0.98);
}

// Whether the placed source boundary lands on the hole's loop vertex for vertex (then the loops are welded).
bool loops_coincide(const Transplant& t, const Points& placed) {
  const auto &bs = t.source_patch.boundary, &bt = t.patch.boundary;
  if (bs.size() != bt.size()) return false;
  const double tol = 1e-9 * bbox_diagonal(t.patch.mesh.V);
  for (std::size_t k = 0; k < bs.size(); ++k)
    if ((placed.row(bs[k]) - t.patch.mesh.V.row(bt[k])).norm() > tol) return false;
  return true;
}

double loop_angle(const UV& uv, int v) {
  const double a = std::atan2(uv(v, 1), uv(v, 0));
  return a < 0 ? a + 2 * M_PI : a;
}

ZipperLoop zipper_loop(const DiskPatch& p, const UV& uv, const std::vector<int>& result_id, const Points& at) {
  ZipperLoop l;
  for (int v : p.boundary) {
    l.ids.push_back(result_id[v]);
    l.angle.push_back(loop_angle(uv, v));
  }
  l.at.resize(static_cast<Eigen::Index>(l.ids.size()), 3);
  for (std::size_t k = 0; k < l.ids.size(); ++k) l.at.row(static_cast<Eigen::Index>(k)) = at.row(l.ids[k]);
  return l;
}

// The joined mesh's vertex numbering: the target's vertices outside the region's interior, then the source
// patch's (its boundary onto the hole's loop when welded).
void number_vertices(Transplant& t, const Mesh& target, std::vector<int>& new_id) {
  const DiskPatch &p = t.patch, &s = t.source_patch;
  std::vector<char> removed(static_cast<std::size_t>(target.num_vertices()), 0);
  for (int l = 0; l < p.num_vertices(); ++l) removed[p.parent[l]] = !p.on_boundary[l];
  new_id.assign(static_cast<std::size_t>(target.num_vertices()), -1);
  for (int v = 0; v < target.num_vertices(); ++v)
    if (!removed[v]) {
      new_id[v] = static_cast<int>(t.kept.size());
      t.kept.push_back(v);
    }
  t.kept_vertices = static_cast<int>(t.kept.size());
  t.source_in_result.assign(static_cast<std::size_t>(s.num_vertices()), -1);
  if (t.welded)
    for (std::size_t k = 0; k < s.boundary.size(); ++k) t.source_in_result[s.boundary[k]] = new_id[p.parent[p.boundary[k]]];
  int next = t.kept_vertices;
  for (int& r : t.source_in_result)
    if (r < 0) r = next++;
  t.result.V.resize(next, 3);
  t.result.name = target.name + "_transplant";
}

// The band between the hole's loop (outer) and the source's boundary (inner), zippered in the target's shape `Xt`
// (positions on the joined mesh): by parameter angle, or, with the target's normals along the hole's loop, by
// the shorter diagonal avoiding folds (applications/zipper.h).
Faces band_faces(const Transplant& t, const Mesh& target, const UV& uv_t, const UV& uv_s,
                 const std::vector<int>& new_id, const Points& Xt, bool by_diagonal) {
  const DiskPatch& p = t.patch;
  std::vector<int> outer_id(static_cast<std::size_t>(p.num_vertices()), -1);
  for (int l : p.boundary) outer_id[l] = new_id[p.parent[l]];
  ZipperLoop outer = zipper_loop(p, uv_t, outer_id, Xt);
  if (by_diagonal) {
    const Points N = vertex_normals(target.V, target.F);
    outer.normal.resize(outer.at.rows(), 3);
    for (std::size_t k = 0; k < p.boundary.size(); ++k)
      outer.normal.row(static_cast<Eigen::Index>(k)) = N.row(p.parent[p.boundary[k]]);
  }
  return zipper_band(outer, zipper_loop(t.source_patch, uv_s, t.source_in_result, Xt));
}

// The joined mesh's faces: the target's outside the region, the source patch's, then the band.
void join_faces(Transplant& t, const Mesh& target, const std::vector<int>& new_id, const Faces& band) {
  std::vector<char> in_patch(static_cast<std::size_t>(target.num_vertices()), 0);
  for (int v : t.patch.parent) in_patch[v] = 1;
  std::vector<int> faces;
  for (int f = 0; f < target.num_faces(); ++f) {
    const auto c = target.F.row(f);
    if (in_patch[c(0)] && in_patch[c(1)] && in_patch[c(2)]) continue;  // a region face: cut out
    if (new_id[c(0)] < 0 || new_id[c(1)] < 0 || new_id[c(2)] < 0)
      throw InputError(fmt::format("target face {} touches the region's interior from outside it: the region's "
                                   "neighbourhood is not manifold", f));
    faces.push_back(f);
  }
  const DiskPatch& s = t.source_patch;
  t.band_faces = static_cast<int>(band.rows());
  Faces& F = t.result.F;
  F.resize(static_cast<Eigen::Index>(faces.size()) + s.mesh.num_faces() + band.rows(), 3);
  Eigen::Index r = 0;
  for (int f : faces) F.row(r++) << new_id[target.F(f, 0)], new_id[target.F(f, 1)], new_id[target.F(f, 2)];
  for (int f = 0; f < s.mesh.num_faces(); ++f)
    for (int c = 0; c < 3; ++c) F(r + f, c) = t.source_in_result[s.mesh.F(f, c)];
  F.bottomRows(band.rows()) = band;
}

// Positions on the joined mesh: the kept target's own, and per source vertex `src` (a row per patch vertex).
Points joined_positions(const Transplant& t, const Mesh& target, const Points& src) {
  Points X(t.result.num_vertices(), 3);
  for (int r = 0; r < t.kept_vertices; ++r) X.row(r) = target.V.row(t.kept[r]);
  for (int l = 0; l < t.source_patch.num_vertices(); ++l)
    if (t.source_in_result[l] >= t.kept_vertices) X.row(t.source_in_result[l]) = src.row(l);
  return X;
}

double smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3 - 2 * x);
}

}  // namespace

namespace {

// Places the source at parameter radius rho: `shape` gets the target surface at each source vertex's scaled
// parameter point, `placed` the source moved by the similarity that fits its boundary onto `shape`'s.
void place_at(Transplant& t, const UV& uv_t, const UV& uv_s, double rho, Points& placed, Points& shape) {
  t.rho = rho;
  shape = surface_at(t.patch, uv_t, rho * uv_s);
  placed = place_source(t.source_patch, shape, t.scale);
}

// Joins with the band zippered by angle, unless the one zippered by the shorter diagonal has a smaller largest
// dihedral angle along it in the target's shape: the angle's order follows the parameterization, which near a
// staircase of the hole's loop folds the band in space; the diagonal's follows the geometry.
void join_with_band(Transplant& t, const Mesh& target, const UV& uv_t, const UV& uv_s,
                    const std::vector<int>& new_id, const Points& Xt) {
  double best = 0;
  for (bool by_diagonal : {false, true}) {
    const Faces band = band_faces(t, target, uv_t, uv_s, new_id, Xt, by_diagonal);
    join_faces(t, target, new_id, band);
    const double angle = band_angles(Mesh{Xt, t.result.F, ""}, t.result.num_faces() - t.band_faces).max_deg;
    if (!by_diagonal || angle < best) {
      best = angle;
      t.band_by_diagonal = by_diagonal;
    }
  }
  if (!t.band_by_diagonal) join_faces(t, target, new_id, band_faces(t, target, uv_t, uv_s, new_id, Xt, false));
}

// Detail error over the source vertices with blend 1 (against `wanted`, the placed source's Laplacian
// coordinates) and the seam's angles before and after.
void measure(Transplant& t, const Mesh& target, const Points& wanted, const Adjacency& adj) {
  const Points got = uniform_delta(t.result, adj);
  double err2 = 0, ref2 = 0;
  for (int l = 0; l < t.source_patch.num_vertices(); ++l) {
    const int r = t.source_in_result[l];
    if (t.blend[l] < 1.0 || r < t.kept_vertices) continue;
    ++t.core_vertices;
    err2 += (got.row(r) - wanted.row(r)).squaredNorm();
    ref2 += wanted.row(r).squaredNorm();
  }
  t.detail_error = ref2 > 0 ? std::sqrt(err2 / ref2) : 0.0;
  t.seam_before = seam_angles(target, t.patch);
  if (!t.welded) {
    t.seam_after = band_angles(t.result, t.result.num_faces() - t.band_faces);
    return;
  }
  std::vector<std::pair<int, int>> loop;  // the welded seam: the source boundary's edges in the result
  const auto& b = t.source_patch.boundary;
  for (std::size_t k = 0; k < b.size(); ++k)
    loop.emplace_back(t.source_in_result[b[k]], t.source_in_result[b[(k + 1) % b.size()]]);
  t.seam_after = dihedral_angles(t.result, loop);
}

}  // namespace

Transplant transplant_patch(const Mesh& source, const std::vector<int>& source_region, const Mesh& target,
                            const std::vector<int>& target_region, const TransplantOptions& options) {
  Transplant out;
  out.source_patch = extract_disk_patch(source, source_region, "source", Ears::Trim);
  out.patch = extract_disk_patch(target, target_region, "target", Ears::Trim);
  Timer t;
  const UV uv_s = tutte_parameterization(out.source_patch), uv_t = tutte_parameterization(out.patch);
  out.parameterize_s = t.seconds();
  t.reset();
  Points placed, shape;
  place_at(out, uv_t, uv_s, 1.0, placed, shape);  // onto the hole's own loop: welded when they coincide
  out.welded = loops_coincide(out, placed);
  std::vector<int> new_id;
  number_vertices(out, target, new_id);
  if (!out.welded) place_at(out, uv_t, uv_s, inner_ring_radius(out.patch, uv_t), placed, shape);
  const Points Xs = joined_positions(out, target, placed), Xt = joined_positions(out, target, shape);
  if (out.welded) join_faces(out, target, new_id, Faces(0, 3));
  else join_with_band(out, target, uv_t, uv_s, new_id, Xt);
  const Adjacency adj = vertex_adjacency(out.result);
  const Points Ls = uniform_delta(Mesh{Xs, out.result.F, ""}, adj), Lt = uniform_delta(Mesh{Xt, out.result.F, ""}, adj);
  // The target's shape everywhere, the source's blended in over the source's vertices.
  Points delta = Lt;
  std::vector<Constraint> kinds(static_cast<std::size_t>(out.result.num_vertices()), Constraint::Hard);
  out.blend.resize(static_cast<std::size_t>(out.source_patch.num_vertices()));
  for (int l = 0; l < out.source_patch.num_vertices(); ++l) {
    out.blend[l] = out.source_patch.on_boundary[l] ? 0.0 : smoothstep((1.0 - uv_s.row(l).norm()) / options.zone);
    const int r = out.source_in_result[l];
    if (r < out.kept_vertices) continue;  // welded onto the target's loop
    delta.row(r) += out.blend[l] * (Ls.row(r) - Lt.row(r));
    kinds[r] = Constraint::Free;
  }
  out.map_s = t.seconds();
  out.result.V = out.placed = Xs;
  out.result.V = solve_lse(out.result, kinds, 1.0, delta, Xs, &out.solve);
  measure(out, target, Ls, adj);
  return out;
}

}  // namespace db
