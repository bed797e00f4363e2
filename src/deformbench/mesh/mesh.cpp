#include "mesh/mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include "core/error.h"

namespace db {

namespace {

std::string label(const Mesh& mesh) { return mesh.name.empty() ? std::string("mesh") : "mesh '" + mesh.name + "'"; }

// Faces incident to each vertex, CSR (vertex -> face ids). Assumes indices were range-checked.
void vertex_faces(const Mesh& mesh, std::vector<int>& off, std::vector<int>& fid) {
  const int nv = mesh.num_vertices(), nf = mesh.num_faces();
  off.assign(nv + 1, 0);
  for (int f = 0; f < nf; ++f)
    for (int c = 0; c < 3; ++c) ++off[mesh.F(f, c) + 1];
  std::partial_sum(off.begin(), off.end(), off.begin());
  fid.resize(off[nv]);
  std::vector<int> pos(off.begin(), off.end() - 1);
  for (int f = 0; f < nf; ++f)
    for (int c = 0; c < 3; ++c) fid[pos[mesh.F(f, c)]++] = f;
}

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
  std::vector<int> raw(cnt[nv]);
  std::vector<int> pos(cnt.begin(), cnt.end() - 1);
  for (int f = 0; f < nf; ++f)
    for (int c = 0; c < 3; ++c) {
      const int v = mesh.F(f, c);
      raw[pos[v]++] = mesh.F(f, (c + 1) % 3);
      raw[pos[v]++] = mesh.F(f, (c + 2) % 3);
    }
  Adjacency adj;
  adj.off.resize(nv + 1);
  adj.nbr.reserve(raw.size() / 2 + nv);
  adj.off[0] = 0;
  for (int v = 0; v < nv; ++v) {
    int* b = raw.data() + cnt[v];
    int* e = raw.data() + cnt[v + 1];
    std::sort(b, e);
    e = std::unique(b, e);
    for (int* p = b; p != e; ++p)
      if (*p != v) adj.nbr.push_back(*p);  // a repeated corner must not make a vertex its own neighbour
    adj.off[v + 1] = static_cast<int>(adj.nbr.size());
  }
  return adj;
}

double bbox_diagonal(const Points& V) {
  if (V.rows() == 0) return 0.0;
  // stableNorm: the plain norm squares, which over- or underflows for extents beyond ~1e154 or below ~1e-154.
  return (V.colwise().maxCoeff() - V.colwise().minCoeff()).stableNorm();
}

void validate_mesh(const Mesh& mesh) {
  const std::string who = label(mesh);
  const int nv = mesh.num_vertices(), nf = mesh.num_faces();
  if (nv == 0) throw InputError(who + " is empty (no vertices)");
  if (nf == 0) throw InputError(who + " is empty (no faces)");

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

  // Area relative to the squared diagonal, on coordinates divided by it: scale invariant, and neither tiny nor huge
  // models under- or overflow.
  double diag = 0;
  try {
    diag = checked_bbox_diagonal(mesh.V);
  } catch (const InputError& e) {
    throw InputError(who + ": " + e.what());
  }
  const double s = diag > 0 ? 1.0 / diag : 1.0;
  for (int f = 0; f < nf; ++f) {
    const int a = mesh.F(f, 0), b = mesh.F(f, 1), c = mesh.F(f, 2);
    if (a == b || b == c || a == c)
      throw InputError(fmt::format("{}: face {} is degenerate (repeated corner: {} {} {})", who, f, a, b, c));
    const Vec3 pa = mesh.V.row(a), pb = mesh.V.row(b), pc = mesh.V.row(c);
    const double area = 0.5 * (s * (pb - pa)).cross(s * (pc - pa)).norm();
    if (!(area >= 1e-14))
      throw InputError(fmt::format("{}: face {} is degenerate (area {:.3g} x bbox_diagonal^2, under 1e-14)", who, f,
                                   area));
  }

  std::vector<int> vf_off, vf;
  vertex_faces(mesh, vf_off, vf);
  for (int v = 0; v < nv; ++v)
    if (vf_off[v] == vf_off[v + 1]) throw InputError(fmt::format("{}: vertex {} is isolated (in no face)", who, v));

  // Per vertex v, the link: the edge opposite v in each incident face. A link vertex w used by more than two link
  // edges means edge (v, w) has more than two faces; with manifold edges, the incident faces form a single fan
  // exactly when the link is connected. Local work only, so O(F log valence) overall.
  std::vector<int> local, parent;
  for (int v = 0; v < nv; ++v) {
    local.clear();
    for (int k = vf_off[v]; k < vf_off[v + 1]; ++k) {
      const int f = vf[k];
      for (int c = 0; c < 3; ++c)
        if (mesh.F(f, c) != v) local.push_back(mesh.F(f, c));
    }
    std::sort(local.begin(), local.end());
    for (std::size_t i = 0; i < local.size();) {
      std::size_t j = i + 1;
      while (j < local.size() && local[j] == local[i]) ++j;
      if (j - i > 2)
        throw InputError(fmt::format("{}: non-manifold edge ({}, {}) shared by {} faces", who, std::min(v, local[i]),
                                     std::max(v, local[i]), j - i));
      i = j;
    }
    local.erase(std::unique(local.begin(), local.end()), local.end());
    parent.resize(local.size());
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](int x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    auto id = [&](int w) { return static_cast<int>(std::lower_bound(local.begin(), local.end(), w) - local.begin()); };
    int components = static_cast<int>(local.size());
    for (int k = vf_off[v]; k < vf_off[v + 1]; ++k) {
      const int f = vf[k];
      int c = 0;
      while (mesh.F(f, c) != v) ++c;
      const int ra = find(id(mesh.F(f, (c + 1) % 3))), rb = find(id(mesh.F(f, (c + 2) % 3)));
      if (ra != rb) {
        parent[ra] = rb;
        --components;
      }
    }
    if (components > 1)
      throw InputError(fmt::format("{}: non-manifold vertex {} (its {} incident faces form {} separate fans)", who, v,
                                   vf_off[v + 1] - vf_off[v], components));
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

}  // namespace db
