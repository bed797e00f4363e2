#include "mesh/mesh.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include "solvers/base/error.h"
#include "solvers/base/resources.h"

namespace db {

namespace {

std::string label(const Mesh& mesh) { return mesh.name.empty() ? std::string("mesh") : "mesh '" + mesh.name + "'"; }

}  // namespace

Adjacency vertex_adjacency(const Mesh& mesh) {
  const int nv = mesh.num_vertices(), nf = mesh.num_faces();
  // Every corner contributes its two face-neighbours; duplicates (shared edges) are removed per vertex.
  std::vector<int> cnt(nv + 1, 0);
  for (int f = 0; f < nf; ++f)
    for (int c = 0; c < 3; ++c) {
      const int v = mesh.F(f, c);
      if (v < 0 || v >= nv)
        throw InputError(fmt::format("{}: face {} has corner index {} out of range [0, {})", label(mesh), f, v, nv));
      cnt[v + 1] += 2;
    }
  std::partial_sum(cnt.begin(), cnt.end(), cnt.begin());
  // The neighbours scattered into each vertex's slots by face ranges on the worker threads (cache misses, most of
  // this function's time): the slots' order then depends on the threads' timing, but each list is sorted next.
  std::vector<int> raw(cnt[nv]);
  std::unique_ptr<std::atomic<int>[]> pos(new std::atomic<int>[static_cast<std::size_t>(nv)]);
  for (int v = 0; v < nv; ++v) pos[v].store(cnt[v], std::memory_order_relaxed);
  run_ranges(nf, 4096, [&](int lo, int hi) {
    for (int f = lo; f < hi; ++f)
      for (int c = 0; c < 3; ++c) {
        const int at = pos[mesh.F(f, c)].fetch_add(2, std::memory_order_relaxed);
        raw[at] = mesh.F(f, (c + 1) % 3);
        raw[at + 1] = mesh.F(f, (c + 2) % 3);
      }
  });
  // Each vertex's list sorted and made unique in place, then packed, by vertex ranges on the worker threads.
  Adjacency adj;
  adj.off.assign(nv + 1, 0);
  run_ranges(nv, 4096, [&](int lo, int hi) {
    for (int v = lo; v < hi; ++v) {
      int* b = raw.data() + cnt[v];
      int* e = raw.data() + cnt[v + 1];
      std::sort(b, e);
      e = std::remove(b, std::unique(b, e), v);  // a repeated corner must not make a vertex its own neighbour
      adj.off[v + 1] = static_cast<int>(e - b);
    }
  });
  std::partial_sum(adj.off.begin(), adj.off.end(), adj.off.begin());
  adj.nbr.resize(static_cast<std::size_t>(adj.off[nv]));
  run_ranges(nv, 4096, [&](int lo, int hi) {
    for (int v = lo; v < hi; ++v)
      std::copy(raw.data() + cnt[v], raw.data() + cnt[v] + adj.degree(v), adj.nbr.data() + adj.off[v]);
  });
  return adj;
}

Adjacency vertex_faces(const Mesh& mesh) {
  const int nv = mesh.num_vertices(), nf = mesh.num_faces();
  Adjacency vf;
  vf.off.assign(nv + 1, 0);
  for (int f = 0; f < nf; ++f)
    for (int c = 0; c < 3; ++c) ++vf.off[mesh.F(f, c) + 1];
  std::partial_sum(vf.off.begin(), vf.off.end(), vf.off.begin());
  vf.nbr.resize(vf.off[nv]);
  std::vector<int> pos(vf.off.begin(), vf.off.end() - 1);
  for (int f = 0; f < nf; ++f)
    for (int c = 0; c < 3; ++c) vf.nbr[pos[mesh.F(f, c)]++] = f;
  return vf;
}

double bbox_diagonal(const Points& V) {
  if (V.rows() == 0) return 0.0;
  const Eigen::RowVector3d e = V.colwise().maxCoeff() - V.colwise().minCoeff();
  const double d = e.norm();
  // The plain norm squares: extents beyond ~1e154 or below ~1e-154 over- or underflow there.
  return (d > 1e-150 && d < 1e150) || e.isZero(0) ? d : e.stableNorm();
}

std::string NonManifold::summary() const {
  std::vector<std::string> parts;
  if (!edges.empty()) {
    const Edge& e = edges.front();
    parts.push_back(fmt::format("{} non-manifold edge{} (first: ({}, {}) shared by {} faces)", edges.size(),
                                edges.size() == 1 ? "" : "s", e.a, e.b, e.faces));
  }
  if (!vertices.empty()) {
    const Vertex& v = vertices.front();
    parts.push_back(fmt::format("{} non-manifold vert{} (first: {}, {} faces in {} separate fans)", vertices.size(),
                                vertices.size() == 1 ? "ex" : "ices", v.v, v.faces, v.fans));
  }
  return parts.empty() ? "manifold" : fmt::format("{}", fmt::join(parts, " and "));
}

namespace {

bool repeated_corner(const Mesh& mesh, int f) {
  return mesh.F(f, 0) == mesh.F(f, 1) || mesh.F(f, 1) == mesh.F(f, 2) || mesh.F(f, 0) == mesh.F(f, 2);
}

// The link of v: the edge opposite v in each face around it (`faces`, none with a repeated corner). A link vertex
// w used by more than two link edges means edge (v, w) has more than two faces; the faces form a single fan
// exactly when the link is connected. Appends what it finds to nm.
void check_link(const Mesh& mesh, int v, const std::vector<int>& faces, NonManifold& nm) {
  std::vector<int> local;
  local.reserve(2 * faces.size());
  for (int f : faces)
    for (int c = 0; c < 3; ++c)
      if (mesh.F(f, c) != v) local.push_back(mesh.F(f, c));
  std::sort(local.begin(), local.end());
  for (std::size_t i = 0; i < local.size();) {
    std::size_t j = i + 1;
    while (j < local.size() && local[j] == local[i]) ++j;
    if (j - i > 2 && v < local[i]) nm.edges.push_back({v, local[i], static_cast<int>(j - i)});
    i = j;
  }
  local.erase(std::unique(local.begin(), local.end()), local.end());
  std::vector<int> parent(local.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  auto id = [&](int w) { return static_cast<int>(std::lower_bound(local.begin(), local.end(), w) - local.begin()); };
  int components = static_cast<int>(local.size());
  for (int f : faces) {
    int c = 0;
    while (mesh.F(f, c) != v) ++c;
    const int ra = find(id(mesh.F(f, (c + 1) % 3))), rb = find(id(mesh.F(f, (c + 2) % 3)));
    if (ra != rb) {
      parent[ra] = rb;
      --components;
    }
  }
  if (components > 1) nm.vertices.push_back({v, static_cast<int>(faces.size()), components});
}

}  // namespace

NonManifold find_non_manifold(const Mesh& mesh) {
  // Local work per vertex, so O(F log valence) overall. Faces with a repeated corner are left out (they are
  // degenerate, see degenerate_face).
  const Adjacency around = vertex_faces(mesh);
  NonManifold nm;
  std::vector<int> faces;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    faces.clear();
    for (const int* f = around.begin(v); f != around.end(v); ++f)
      if (!repeated_corner(mesh, *f)) faces.push_back(*f);
    check_link(mesh, v, faces, nm);
  }
  std::sort(nm.edges.begin(), nm.edges.end(), [](const auto& x, const auto& y) {
    return std::make_pair(x.a, x.b) < std::make_pair(y.a, y.b);
  });
  return nm;
}

std::string degenerate_face(const Mesh& mesh, int f, double diag) {
  const int a = mesh.F(f, 0), b = mesh.F(f, 1), c = mesh.F(f, 2);
  if (repeated_corner(mesh, f)) return fmt::format("repeated corner: {} {} {}", a, b, c);
  const double s = diag > 0 ? 1.0 / diag : 1.0;
  const Vec3 pa = mesh.V.row(a), pb = mesh.V.row(b), pc = mesh.V.row(c);
  const double area = 0.5 * (s * (pb - pa)).cross(s * (pc - pa)).norm();
  if (!(area >= 1e-14)) return fmt::format("area {:.3g} x bbox_diagonal^2, under 1e-14 x bbox_diagonal^2", area);
  return {};
}

void check_arrays(const Mesh& mesh) {
  const std::string who = label(mesh);
  const int nv = mesh.num_vertices(), nf = mesh.num_faces();
  for (int v = 0; v < nv; ++v)
    if (!mesh.V.row(v).allFinite())
      throw InputError(fmt::format("{}: vertex {} has a non-finite coordinate ({}, {}, {})", who, v, mesh.V(v, 0),
                                   mesh.V(v, 1), mesh.V(v, 2)));
  for (int f = 0; f < nf; ++f)
    for (int c = 0; c < 3; ++c) {
      const int v = mesh.F(f, c);
      if (v < 0 || v >= nv)
        throw InputError(fmt::format("{}: face {} has corner index {} out of range [0, {})", who, f, v, nv));
    }
}

namespace {

constexpr const char* kRepairHint = "`meshtool repair IN OUT` fixes it";

}  // namespace

void validate_mesh(const Mesh& mesh, Manifold manifold) {
  const std::string who = label(mesh);
  const int nv = mesh.num_vertices(), nf = mesh.num_faces();
  if (nv == 0) throw InputError(who + " is empty (no vertices)");
  if (nf == 0) throw InputError(who + " is empty (no faces)");
  check_arrays(mesh);

  // Named when a double cannot hold the extent (a plain norm would over- or underflow into a false verdict).
  double diag = 0;
  try {
    diag = checked_bbox_diagonal(mesh.V);
  } catch (const InputError& e) {
    throw InputError(who + ": " + e.what());
  }
  for (int f = 0; f < nf; ++f) {
    const std::string why = degenerate_face(mesh, f, diag);
    if (!why.empty()) throw InputError(fmt::format("{}: face {} is degenerate ({}); {}", who, f, why, kRepairHint));
  }

  std::vector<bool> used(nv, false);
  for (int f = 0; f < nf; ++f)
    for (int c = 0; c < 3; ++c) used[mesh.F(f, c)] = true;
  for (int v = 0; v < nv; ++v)
    if (!used[v]) throw InputError(fmt::format("{}: vertex {} is isolated (in no face); {}", who, v, kRepairHint));

  if (manifold == Manifold::Allowed) return;
  const NonManifold nm = find_non_manifold(mesh);
  if (!nm.edges.empty()) {
    const auto& e = nm.edges.front();
    throw InputError(fmt::format("{}: non-manifold edge ({}, {}) shared by {} faces ({} in all); {}", who, e.a, e.b,
                                 e.faces, nm.summary(), kRepairHint));
  }
  if (!nm.vertices.empty()) {
    const auto& v = nm.vertices.front();
    throw InputError(fmt::format("{}: non-manifold vertex {} (its {} incident faces form {} separate fans; {} in all); "
                                 "{}",
                                 who, v.v, v.faces, v.fans, nm.summary(), kRepairHint));
  }
}

double checked_bbox_diagonal(const Points& V) {
  const double d = bbox_diagonal(V);
  if (std::isfinite(d) && (d == 0 || d >= std::numeric_limits<double>::min())) return d;
  static const char* const kAxis[] = {"x", "y", "z"};
  const Eigen::RowVector3d lo = V.colwise().minCoeff(), hi = V.colwise().maxCoeff();
  Eigen::Index c, imin, imax;
  (hi - lo).maxCoeff(&c);
  V.col(c).minCoeff(&imin);
  V.col(c).maxCoeff(&imax);
  const std::string span =
      fmt::format("vertices {} and {} (their {} coordinates {:g} and {:g})", imin, imax, kAxis[c], lo(c), hi(c));
  if (!std::isfinite(d))
    throw InputError(fmt::format("{} lie farther apart than a double can measure (the bounding-box diagonal "
                                 "overflows); scale the mesh down",
                                 span));
  throw InputError(fmt::format("the bounding-box diagonal {:g} is below the smallest normal double ({:g}): {} keep "
                               "too few digits to deform; scale the mesh up",
                               d, std::numeric_limits<double>::min(), span));
}

std::vector<int> face_components(const Mesh& mesh) {
  std::vector<int> parent(static_cast<std::size_t>(mesh.num_vertices()));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (int f = 0; f < mesh.num_faces(); ++f)
    for (int k = 1; k < 3; ++k) parent[find(mesh.F(f, k))] = find(mesh.F(f, 0));
  std::vector<int> label(static_cast<std::size_t>(mesh.num_vertices()), -1), out;
  int count = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    int& l = label[find(mesh.F(f, 0))];
    if (l < 0) l = count++;
    out.push_back(l);
  }
  return out;
}

int count_components(const Mesh& mesh) {
  const std::vector<int> c = face_components(mesh);
  return c.empty() ? 0 : *std::max_element(c.begin(), c.end()) + 1;
}

}  // namespace db
