#include "applications/coating_transfer.h"

#include <fmt/format.h>

#include "applications/parameter_map.h"
#include "applications/tangent_frames.h"
#include "solvers/base/error.h"
#include "core/timer.h"

namespace db {

const EnumText<DetailEncoding>& enum_text(DetailEncoding) {
  static const EnumText<DetailEncoding> t{
      "detail encoding", {{DetailEncoding::Height, "height"}, {DetailEncoding::Laplacian, "laplacian"}}};
  return t;
}

namespace {

double loop_length(const DiskPatch& p) {
  double len = 0;
  const std::size_t m = p.boundary.size();
  for (std::size_t k = 0; k < m; ++k) len += (p.mesh.V.row(p.boundary[(k + 1) % m]) - p.mesh.V.row(p.boundary[k])).norm();
  return len;
}

// Kinds of the patch's own vertices: its boundary hard, its interior soft (smoothing) or free.
std::vector<Constraint> interior_kinds(const DiskPatch& p, Constraint interior) {
  std::vector<Constraint> kinds(static_cast<std::size_t>(p.num_vertices()), interior);
  for (int v : p.boundary) kinds[static_cast<std::size_t>(v)] = Constraint::Hard;
  return kinds;
}

double mean_edge_length(const Mesh& m) {
  double sum = 0;
  for (int f = 0; f < m.num_faces(); ++f)
    for (int c = 0; c < 3; ++c) sum += (m.V.row(m.F(f, (c + 1) % 3)) - m.V.row(m.F(f, c))).norm();
  return sum / (3.0 * m.num_faces());
}

// E(X) of the encoding, X the whole mesh's positions, on the patch's rows: the positions (height) or their
// uniform Laplacian coordinates (laplacian).
Points encoded(DetailEncoding e, const Mesh& whole, const Adjacency& adj, const DiskPatch& p, const Points& X) {
  const Points all = e == DetailEncoding::Laplacian ? uniform_delta(Mesh{X, whole.F, whole.name}, adj) : X;
  Points out(p.num_vertices(), 3);
  for (int l = 0; l < p.num_vertices(); ++l) out.row(l) = all.row(p.parent[l]);
  return out;
}

// The uniform Laplacian coordinates of the patch's vertices placed at X (patch rows), as rows of the whole mesh's
// Laplacian (the rest of the mesh where it is): a boundary vertex averages over all its neighbours in the mesh, as
// in the rows of the transfer's LSE solve, which runs on the whole target.
Points rows_in_mesh(const Mesh& whole, const Adjacency& adj, const DiskPatch& p, const Points& X) {
  Points placed = whole.V;
  for (int l = 0; l < p.num_vertices(); ++l) placed.row(p.parent[l]) = X.row(l);
  return encoded(DetailEncoding::Laplacian, whole, adj, p, placed);
}

}  // namespace

Coating extract_coating(const Mesh& source, const std::vector<int>& region, const CoatingOptions& options) {
  Coating c;
  c.patch = extract_disk_patch(source, region, "source");
  c.encoding = options.encoding;
  const Mesh& m = c.patch.mesh;
  const Adjacency adj = vertex_adjacency(m);
  // Zero Laplacian coordinates inside; the boundary's rows (they touch interior unknowns, so they are in the
  // energy) keep their own, or their target 0 would pull the interior outwards.
  const Points delta = uniform_delta(m, adj);
  Points target = delta;
  for (int v = 0; v < m.num_vertices(); ++v)
    if (!c.patch.on_boundary[v]) target.row(v).setZero();
  c.smooth = solve_lse(m, interior_kinds(c.patch, Constraint::Soft), options.smooth_weight, target, m.V,
                       &c.smoothing);
  const Mesh smooth{c.smooth, m.F, m.name + "_smooth"};
  Timer t;
  c.uv = disk_parameterization(DiskPatch{smooth, c.patch.parent, c.patch.boundary, c.patch.on_boundary}, options.map);
  c.parameterize_s = t.seconds();
  const std::vector<Mat3> frames = tangent_frames(smooth, adj, c.uv);
  Points d = m.V - c.smooth;
  if (options.encoding == DetailEncoding::Laplacian) {
    // The detail is read back by the rows of the target mesh's Laplacian, so it is written with the source
    // mesh's: with the patch's own, a boundary vertex's detail would be divided by its degree within the patch,
    // not in the mesh, and a surface's own coating would not give it back on a sub-patch.
    const Adjacency whole = vertex_adjacency(source);
    d = rows_in_mesh(source, whole, c.patch, m.V) - rows_in_mesh(source, whole, c.patch, c.smooth);
  }
  c.detail.resize(d.rows(), 3);
  for (Eigen::Index i = 0; i < d.rows(); ++i) c.detail.row(i) = (frames[i].transpose() * d.row(i).transpose()).transpose();
  c.boundary_length = loop_length(c.patch);
  c.mean_edge = mean_edge_length(smooth);  // the spacing of the surface the detail sits on
  return c;
}

Mesh own_smooth_version(const Mesh& source, const Coating& coating) {
  Mesh m = source;
  for (int l = 0; l < coating.patch.num_vertices(); ++l) m.V.row(coating.patch.parent[l]) = coating.smooth.row(l);
  return m;
}

CoatedTarget transfer_coating(const Coating& coating, const Mesh& target, const std::vector<int>& region,
                              const CoatingOptions& options) {
  if (coating.uv.rows() != coating.patch.num_vertices() || coating.detail.rows() != coating.patch.num_vertices())
    throw InputError(fmt::format("coating: {} patch vertices but {} parameter points and {} detail vectors",
                                 coating.patch.num_vertices(), coating.uv.rows(), coating.detail.rows()));
  CoatedTarget out;
  out.patch = extract_disk_patch(target, region, "target");
  const DiskPatch& p = out.patch;
  Timer t;
  const UV uv = disk_parameterization(p, options.map);
  out.parameterize_s = t.seconds();
  t.reset();
  // The detail as a shape scales with the patch (sigma); uniform Laplacian coordinates also scale with the square
  // of the vertex spacing relative to the shape: rho = (h_t / h_s) / sigma.
  out.sigma = loop_length(p) / coating.boundary_length;
  const double rho = mean_edge_length(p.mesh) / coating.mean_edge / out.sigma;
  const bool laplacian = coating.encoding == DetailEncoding::Laplacian;
  out.scale = options.amplitude * out.sigma * (laplacian ? rho * rho : 1.0);
  out.mapped_detail = out.scale * interpolate(locate_in_parameter_domain(coating.uv, coating.patch.mesh.F, uv),
                                              coating.patch.mesh.F, coating.detail);
  const std::vector<Mat3> frames = tangent_frames(p.mesh, vertex_adjacency(p.mesh), uv);
  out.map_s = t.seconds();

  const Adjacency adj = vertex_adjacency(target);
  const Points delta0 = uniform_delta(target, adj);
  std::vector<Constraint> kinds(static_cast<std::size_t>(target.num_vertices()), Constraint::Hard);
  Points moved = target.V;  // height encoding: the target displaced by the coating
  Points delta = delta0;    // laplacian encoding: the coating added to the target's coordinates
  for (int l = 0; l < p.num_vertices(); ++l) {
    const Vec3 d = frames[l] * out.mapped_detail.row(l).transpose();
    if (laplacian) delta.row(p.parent[l]) += d.transpose();
    if (p.on_boundary[l]) continue;
    kinds[p.parent[l]] = Constraint::Free;
    if (!laplacian) moved.row(p.parent[l]) += d.transpose();
  }
  if (!laplacian) delta = uniform_delta(Mesh{moved, target.F, target.name}, adj);
  out.result = target;
  out.result.V = solve_lse(target, kinds, 1.0, delta, target.V, &out.solve);

  // How much of the mapped coating the solved surface carries, read back in the same frames.
  const Points got = encoded(coating.encoding, target, adj, p, out.result.V) -
                     encoded(coating.encoding, target, adj, p, target.V);
  double err2 = 0, ref2 = 0;
  for (int l = 0; l < p.num_vertices(); ++l) {
    if (p.on_boundary[l]) continue;
    const Vec3 xi = frames[l].transpose() * got.row(l).transpose();
    err2 += (xi - out.mapped_detail.row(l).transpose()).squaredNorm();
    ref2 += out.mapped_detail.row(l).squaredNorm();
  }
  out.detail_error = ref2 > 0 ? std::sqrt(err2 / ref2) : 0.0;
  return out;
}

}  // namespace db
