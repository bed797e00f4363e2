#include "mesh/repair.h"

#include <algorithm>
#include <array>
#include <map>
#include <numeric>
#include <stdexcept>
#include <tuple>

#include <fmt/format.h>

#include "solvers/base/error.h"

namespace db {

namespace {

// Faces kept after dropping degenerate ones and those with the corners of an earlier face (any order).
std::vector<int> kept_faces(const Mesh& in, RepairReport& r) {
  const double diag = bbox_diagonal(in.V);
  std::vector<std::pair<std::array<int, 3>, int>> keyed;
  keyed.reserve(in.num_faces());
  for (int f = 0; f < in.num_faces(); ++f) {
    std::string why = degenerate_face(in, f, diag);
    if (!why.empty()) {
      r.degenerate_faces.emplace_back(f, std::move(why));
      continue;
    }
    std::array<int, 3> key = {in.F(f, 0), in.F(f, 1), in.F(f, 2)};
    std::sort(key.begin(), key.end());
    keyed.emplace_back(key, f);
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<int> keep;
  keep.reserve(keyed.size());
  for (std::size_t i = 0; i < keyed.size(); ++i) {
    if (i > 0 && keyed[i].first == keyed[i - 1].first) {
      std::size_t first = i - 1;
      while (first > 0 && keyed[first - 1].first == keyed[i].first) --first;
      r.duplicate_faces.emplace_back(keyed[i].second, keyed[first].second);
    } else {
      keep.push_back(keyed[i].second);
    }
  }
  std::sort(keep.begin(), keep.end());
  std::sort(r.duplicate_faces.begin(), r.duplicate_faces.end());
  return keep;
}

// Face pairs kept joined across each non-manifold edge (a, b), a < b.
using Joins = std::map<std::pair<int, int>, std::vector<std::pair<int, int>>>;

// The corner of face f that is neither a nor b.
int third_corner(const Mesh& m, int f, int a, int b) {
  for (int c = 0; c < 3; ++c)
    if (m.F(f, c) != a && m.F(f, c) != b) return m.F(f, c);
  return -1;
}

// Patches: the faces connected through edges with exactly two faces (what stays of the surface when every
// non-manifold edge is cut). Returns a patch id per face.
std::vector<int> patches(const Mesh& m) {
  std::vector<int> parent(m.num_faces());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  const Adjacency around = vertex_faces(m);
  std::vector<std::pair<int, int>> link;  // (other corner w > v, face)
  for (int v = 0; v < m.num_vertices(); ++v) {
    link.clear();
    for (const int* f = around.begin(v); f != around.end(v); ++f)
      for (int c = 0; c < 3; ++c)
        if (m.F(*f, c) > v) link.emplace_back(m.F(*f, c), *f);
    std::sort(link.begin(), link.end());
    for (std::size_t i = 0; i + 1 < link.size(); ++i)
      if (link[i].first == link[i + 1].first && (i + 2 == link.size() || link[i + 2].first != link[i].first) &&
          (i == 0 || link[i - 1].first != link[i].first))
        parent[find(link[i].second)] = find(link[i + 1].second);
  }
  for (int f = 0; f < m.num_faces(); ++f) parent[f] = find(f);
  return parent;
}

// At an edge with more than two faces, the surface most likely continues across it between two faces that
// traverse it in opposite directions (consistently oriented): first two faces of one patch (the surface closes
// around through other edges, as a solid's two faces at an edge with a fin glued on), then the pairs that meet
// flattest (their directions away from the edge most nearly opposite). The faces left unpaired come apart there.
Joins pair_faces(const Mesh& m, const NonManifold& nm) {
  Joins joins;
  if (nm.edges.empty()) return joins;
  const Adjacency around = vertex_faces(m);
  const std::vector<int> patch = patches(m);
  for (const auto& e : nm.edges) {
    const Vec3 pa = m.V.row(e.a), pb = m.V.row(e.b);
    const Vec3 along = (pb - pa).normalized();
    std::vector<int> fs;
    std::vector<Vec3> dir;
    std::vector<bool> forward;  // traverses a -> b
    for (const int* f = around.begin(e.a); f != around.end(e.a); ++f) {
      const int w = third_corner(m, *f, e.a, e.b);
      if (w < 0 || (m.F(*f, 0) != e.b && m.F(*f, 1) != e.b && m.F(*f, 2) != e.b)) continue;
      Vec3 d = m.V.row(w).transpose() - pa;
      d -= d.dot(along) * along;
      fs.push_back(*f);
      dir.push_back(d.normalized());
      int c = 0;
      while (m.F(*f, c) != e.a) ++c;
      forward.push_back(m.F(*f, (c + 1) % 3) == e.b);
    }
    std::vector<std::tuple<bool, double, int, int>> candidates;  // (other patches, flatness, i, j): best first
    for (std::size_t i = 0; i < fs.size(); ++i)
      for (std::size_t j = i + 1; j < fs.size(); ++j)
        if (forward[i] != forward[j])
          candidates.emplace_back(patch[fs[i]] != patch[fs[j]], dir[i].dot(dir[j]), static_cast<int>(i),
                                  static_cast<int>(j));
    std::sort(candidates.begin(), candidates.end());
    std::vector<bool> used(fs.size(), false);
    auto& pairs = joins[{e.a, e.b}];
    for (const auto& [other_patch, flatness, i, j] : candidates)
      if (!used[i] && !used[j]) {
        used[i] = used[j] = true;
        pairs.emplace_back(fs[i], fs[j]);
      }
  }
  return joins;
}

// Groups the faces around v (ids `fs`) into fans: two faces join when they share an edge (v, w) that has exactly
// two faces, or are a pair `joins` keeps across the input edge (v, w) is a copy of (origin). Returns a fan label
// per face, 0 for the fan of the first face, then in order of first face.
std::vector<int> fans_around(const Mesh& m, int v, const int* fs, int n, const Joins& joins,
                             const std::vector<int>& origin) {
  std::vector<std::pair<int, int>> link;  // (other corner w, local face)
  link.reserve(2 * n);
  for (int k = 0; k < n; ++k)
    for (int c = 0; c < 3; ++c)
      if (m.F(fs[k], c) != v) link.emplace_back(m.F(fs[k], c), k);
  std::sort(link.begin(), link.end());
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  auto join = [&](int a, int b) { parent[find(a)] = find(b); };
  for (std::size_t i = 0; i < link.size();) {
    std::size_t j = i + 1;
    while (j < link.size() && link[j].first == link[i].first) ++j;
    if (j - i == 2) {
      join(link[i].second, link[i + 1].second);
    } else if (j - i > 2) {
      const int a = origin[v], b = origin[link[i].first];
      const auto it = joins.find({std::min(a, b), std::max(a, b)});
      auto local = [&](int f) {
        for (std::size_t q = i; q < j; ++q)
          if (fs[link[q].second] == f) return link[q].second;
        return -1;
      };
      if (it != joins.end())
        for (const auto& [f, g] : it->second)
          if (local(f) >= 0 && local(g) >= 0) join(local(f), local(g));
    }
    i = j;
  }
  std::vector<int> label(n, -1), root_label(n, -1);
  int next = 0;
  for (int k = 0; k < n; ++k) {
    const int root = find(k);
    if (root_label[root] < 0) root_label[root] = next++;
    label[k] = root_label[root];
  }
  return label;
}

// Gives every fan after the first of each vertex its own copy of the vertex (appended to m.V); origin[v] is the
// input vertex v copies, extended for the copies.
void split_fans(Mesh& m, const Joins& joins, std::vector<int>& origin, std::map<int, std::vector<int>>& copies) {
  const Adjacency around = vertex_faces(m);
  const int nv = m.num_vertices();
  std::vector<Vec3> added;
  for (int v = 0; v < nv; ++v) {
    const int n = around.degree(v);
    const std::vector<int> label = fans_around(m, v, around.begin(v), n, joins, origin);
    const int fans = n == 0 ? 0 : *std::max_element(label.begin(), label.end()) + 1;
    std::vector<int> ids;
    for (int k = 1; k < fans; ++k) {
      ids.push_back(nv + static_cast<int>(added.size()));
      added.push_back(m.V.row(v).transpose());
      origin.push_back(origin[v]);
      copies[origin[v]].push_back(ids.back());
    }
    for (int k = 0; k < n; ++k) {
      if (label[k] == 0) continue;
      const int f = around.begin(v)[k];
      for (int c = 0; c < 3; ++c)
        if (m.F(f, c) == v) m.F(f, c) = ids[label[k] - 1];
    }
  }
  m.V.conservativeResize(nv + static_cast<Eigen::Index>(added.size()), 3);
  for (std::size_t i = 0; i < added.size(); ++i) m.V.row(nv + static_cast<Eigen::Index>(i)) = added[i].transpose();
}

// Removes vertices in no face; fills r.vertex_map and renumbers the copies in r.splits.
void remove_isolated(Mesh& m, int input_vertices, RepairReport& r) {
  const int nv = m.num_vertices();
  std::vector<int> map(nv, -1);
  for (int f = 0; f < m.num_faces(); ++f)
    for (int c = 0; c < 3; ++c) map[m.F(f, c)] = 0;
  int next = 0;
  for (int v = 0; v < nv; ++v) {
    if (map[v] < 0) {
      r.isolated_vertices.push_back(v);  // copies are never isolated: v is an input vertex
      continue;
    }
    m.V.row(next) = m.V.row(v);
    map[v] = next++;
  }
  m.V.conservativeResize(next, 3);
  for (int f = 0; f < m.num_faces(); ++f)
    for (int c = 0; c < 3; ++c) m.F(f, c) = map[m.F(f, c)];
  for (auto& s : r.splits)
    for (int& c : s.copies) c = map[c];
  r.vertex_map.assign(map.begin(), map.begin() + input_vertices);
}

}  // namespace

namespace {

// The output components that came off an input component (output face i is input face keep[i]): all but the
// largest of each, so that following the repair's advice never hides a mesh falling apart.
void detached_pieces(const std::vector<int>& before, const std::vector<int>& after, const std::vector<int>& keep,
                     RepairReport& r) {
  r.components_before = before.empty() ? 0 : *std::max_element(before.begin(), before.end()) + 1;
  r.components_after = after.empty() ? 0 : *std::max_element(after.begin(), after.end()) + 1;
  std::vector<int> faces(r.components_after, 0), from(r.components_after, -1);
  for (std::size_t f = 0; f < after.size(); ++f) {
    ++faces[after[f]];
    from[after[f]] = before[keep[f]];
  }
  std::vector<int> largest(r.components_before, -1);  // output component kept per input component
  for (int c = 0; c < r.components_after; ++c)
    if (largest[from[c]] < 0 || faces[c] > faces[largest[from[c]]]) largest[from[c]] = c;
  for (int c = 0; c < r.components_after; ++c)
    if (largest[from[c]] != c) r.detached.push_back({faces[c], from[c], faces[largest[from[c]]]});
}

}  // namespace

Mesh repair_mesh(const Mesh& in, RepairReport& r) {
  r = RepairReport{};
  check_arrays(in);
  const std::vector<int> keep = kept_faces(in, r);
  Mesh m;
  m.name = in.name;
  m.V = in.V;
  m.F.resize(static_cast<Eigen::Index>(keep.size()), 3);
  for (std::size_t i = 0; i < keep.size(); ++i) m.F.row(static_cast<Eigen::Index>(i)) = in.F.row(keep[i]);
  r.non_manifold = find_non_manifold(m);
  std::vector<int> origin(m.num_vertices());
  std::iota(origin.begin(), origin.end(), 0);
  std::map<int, std::vector<int>> copies;
  split_fans(m, pair_faces(m, r.non_manifold), origin, copies);
  // Kept pairs can, rarely, still leave an edge with three faces in one fan; cutting every such edge cannot.
  if (!find_non_manifold(m).empty()) split_fans(m, {}, origin, copies);
  for (auto& [v, c] : copies) r.splits.push_back({v, std::move(c)});
  remove_isolated(m, in.num_vertices(), r);
  if (m.num_faces() == 0)
    throw InputError(fmt::format("mesh '{}': no face is left after dropping {} degenerate and {} duplicate faces",
                                 in.name, r.degenerate_faces.size(), r.duplicate_faces.size()));
  if (!find_non_manifold(m).empty())  // split_fans leaves at most two faces on an edge, one fan per vertex
    throw std::logic_error("repair_mesh: the split left a non-manifold element");
  detached_pieces(face_components(in), face_components(m), keep, r);
  return m;
}

std::string RepairReport::summary() const {
  if (!changed()) return "no change";
  std::size_t copies = 0;
  for (const Split& s : splits) copies += s.copies.size();
  std::vector<std::string> parts;
  if (!degenerate_faces.empty()) parts.push_back(fmt::format("dropped {} degenerate faces", degenerate_faces.size()));
  if (!duplicate_faces.empty()) parts.push_back(fmt::format("dropped {} duplicate faces", duplicate_faces.size()));
  if (!splits.empty())
    parts.push_back(fmt::format("split {} vertices into {} more ({})", splits.size(), copies, non_manifold.summary()));
  if (!isolated_vertices.empty())
    parts.push_back(fmt::format("removed {} isolated vertices", isolated_vertices.size()));
  if (!detached.empty())
    parts.push_back(fmt::format("detached {} pieces ({} connected components before, {} after)", detached.size(),
                                components_before, components_after));
  return fmt::format("{}", fmt::join(parts, "; "));
}

std::vector<std::string> RepairReport::details(std::size_t max_per_kind) const {
  std::vector<std::string> out;
  auto list = [&](std::size_t n, auto&& line) {
    const std::size_t shown = max_per_kind == 0 ? n : std::min(n, max_per_kind);
    for (std::size_t i = 0; i < shown; ++i) out.push_back(line(i));
    if (shown < n) out.push_back(fmt::format("  ... and {} more", n - shown));
  };
  list(degenerate_faces.size(), [&](std::size_t i) {
    return fmt::format("dropped face {}: degenerate ({})", degenerate_faces[i].first, degenerate_faces[i].second);
  });
  list(duplicate_faces.size(), [&](std::size_t i) {
    return fmt::format("dropped face {}: duplicate of face {}", duplicate_faces[i].first, duplicate_faces[i].second);
  });
  list(non_manifold.edges.size(), [&](std::size_t i) {
    const auto& e = non_manifold.edges[i];
    return fmt::format("non-manifold edge ({}, {}): {} faces", e.a, e.b, e.faces);
  });
  list(non_manifold.vertices.size(), [&](std::size_t i) {
    const auto& v = non_manifold.vertices[i];
    return fmt::format("non-manifold vertex {}: {} faces in {} fans", v.v, v.faces, v.fans);
  });
  list(splits.size(), [&](std::size_t i) {
    const Split& s = splits[i];
    return fmt::format("split vertex {} into {}, {}", s.vertex, vertex_map[s.vertex], fmt::join(s.copies, ", "));
  });
  list(isolated_vertices.size(),
       [&](std::size_t i) { return fmt::format("removed isolated vertex {}", isolated_vertices[i]); });
  list(detached.size(), [&](std::size_t i) {
    const Piece& p = detached[i];
    return fmt::format("detached a piece of {} faces from component {} (which keeps {} faces)", p.faces, p.from,
                       p.from_kept);
  });
  return out;
}

}  // namespace db
