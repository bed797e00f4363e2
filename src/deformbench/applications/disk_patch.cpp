#include "applications/disk_patch.h"

#include <algorithm>
#include <map>
#include <numeric>
#include <utility>

#include <fmt/format.h>

#include "solvers/base/error.h"

namespace db {
namespace {

// Per vertex of `mesh`: whether `region` selects it (ids checked). Returns how many distinct vertices it selects.
int mark_region(const Mesh& mesh, const std::vector<int>& region, const std::string& what, std::vector<char>& in) {
  const int n = mesh.num_vertices();
  in.assign(static_cast<std::size_t>(n), 0);
  int selected = 0;
  for (int v : region) {
    if (v < 0 || v >= n) throw InputError(fmt::format("{} region: vertex {} is out of range (the mesh has {})", what, v, n));
    selected += !in[static_cast<std::size_t>(v)];
    in[static_cast<std::size_t>(v)] = 1;
  }
  return selected;
}

// Unmarks the ears of the marked region (Ears::Trim) until none is left.
void unmark_ears(const Mesh& mesh, std::vector<char>& in) {
  for (bool changed = true; changed;) {
    std::vector<int> faces(in.size(), 0);
    for (int f = 0; f < mesh.num_faces(); ++f)
      if (in[mesh.F(f, 0)] && in[mesh.F(f, 1)] && in[mesh.F(f, 2)])
        for (int c = 0; c < 3; ++c) ++faces[mesh.F(f, c)];
    changed = false;
    for (std::size_t v = 0; v < in.size(); ++v)
      if (in[v] && faces[v] == 1) in[v] = 0, changed = true;
  }
}

// The faces of `mesh` inside the region (without its ears for Ears::Trim), renumbered locally; fills parent.
void cut_faces(const Mesh& mesh, const std::vector<int>& region, const std::string& what, Ears ears, DiskPatch& p) {
  std::vector<char> in;
  const int selected = mark_region(mesh, region, what, in);
  if (ears == Ears::Trim) unmark_ears(mesh, in);
  std::vector<int> faces;
  for (int f = 0; f < mesh.num_faces(); ++f)
    if (in[mesh.F(f, 0)] && in[mesh.F(f, 1)] && in[mesh.F(f, 2)]) faces.push_back(f);
  if (faces.empty())  // the count is the selection's, before any trimming
    throw InputError(fmt::format("{} region holds no whole face of {}{} ({} {} selected): the patch is empty", what,
                                 mesh.name, ears == Ears::Trim ? " once its ears are trimmed" : "", selected,
                                 selected == 1 ? "vertex" : "vertices"));
  const int n = mesh.num_vertices();
  std::vector<int> local(static_cast<std::size_t>(n), -1);
  p.mesh.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t k = 0; k < faces.size(); ++k)
    for (int c = 0; c < 3; ++c) {
      int& l = local[mesh.F(faces[k], c)];
      if (l < 0) {
        l = static_cast<int>(p.parent.size());
        p.parent.push_back(mesh.F(faces[k], c));
      }
      p.mesh.F(static_cast<Eigen::Index>(k), c) = l;
    }
  p.mesh.V.resize(static_cast<Eigen::Index>(p.parent.size()), 3);
  for (std::size_t l = 0; l < p.parent.size(); ++l) p.mesh.V.row(static_cast<Eigen::Index>(l)) = mesh.V.row(p.parent[l]);
  p.mesh.name = mesh.name + "_" + what + "_patch";
}

// The boundary half-edges a -> b (those whose reverse is in no face), checked to form exactly one simple loop.
void trace_boundary(DiskPatch& p, const std::string& what) {
  const Mesh& m = p.mesh;
  std::map<std::pair<int, int>, int> half;  // directed edge -> faces using it
  for (int f = 0; f < m.num_faces(); ++f)
    for (int c = 0; c < 3; ++c) ++half[{m.F(f, c), m.F(f, (c + 1) % 3)}];
  std::vector<int> next(static_cast<std::size_t>(m.num_vertices()), -1);
  int boundary_edges = 0;
  for (const auto& [e, count] : half) {
    const auto rev = half.find({e.second, e.first});
    if (count > 1 || (rev != half.end() && rev->second > 1))
      throw InputError(fmt::format("{} patch is not a disk: edge ({}, {}) of {} is non-manifold or inconsistently "
                                   "oriented", what, p.parent[e.first], p.parent[e.second], m.name));
    if (rev != half.end()) continue;
    if (next[e.first] >= 0)
      throw InputError(fmt::format("{} patch is not a disk: its boundary touches itself at vertex {} (a pinched vertex)",
                                   what, p.parent[e.first]));
    next[e.first] = e.second;
    ++boundary_edges;
  }
  if (boundary_edges == 0)
    throw InputError(fmt::format("{} patch is not a disk: it has no boundary (a closed surface); select part of it",
                                 what));
  int start = -1;
  for (int v = 0; v < m.num_vertices(); ++v)
    if (next[v] >= 0 && (start < 0 || p.parent[v] < p.parent[start])) start = v;
  p.on_boundary.assign(static_cast<std::size_t>(m.num_vertices()), 0);
  for (int v = start; p.boundary.empty() || v != start; v = next[v]) {
    // A boundary vertex entered twice (or a dead end) is no simple loop; the step bound keeps the walk finite.
    if (v < 0 || p.on_boundary[v] || static_cast<int>(p.boundary.size()) == boundary_edges)
      throw InputError(fmt::format("{} patch is not a disk: its boundary is no simple loop", what));
    p.boundary.push_back(v);
    p.on_boundary[v] = 1;
  }
  if (static_cast<int>(p.boundary.size()) != boundary_edges)
    throw InputError(fmt::format("{} patch is not a disk: its boundary has {} edges in more than one loop (a hole or "
                                 "an annulus; the patch needs exactly one)", what, boundary_edges));
}

}  // namespace

DiskPatch extract_disk_patch(const Mesh& mesh, const std::vector<int>& region, const std::string& what, Ears ears) {
  DiskPatch p;
  cut_faces(mesh, region, what, ears, p);
  const int components = count_components(p.mesh);
  if (components != 1)
    throw InputError(fmt::format("{} patch is not a disk: the region's faces form {} separate pieces", what, components));
  trace_boundary(p, what);
  // V - E + F = 1 for a disk; with one boundary loop and one component, anything else has handles (genus).
  const long long V = p.mesh.num_vertices(), F = p.mesh.num_faces();
  const long long E = (3 * F + static_cast<long long>(p.boundary.size())) / 2;
  if (V - E + F != 1)
    throw InputError(fmt::format("{} patch is not a disk: Euler characteristic {} (a handle or tunnel inside it)", what,
                                 V - E + F));
  if (p.boundary.size() == p.parent.size())
    throw InputError(fmt::format("{} patch has no interior vertex (all {} of its vertices are on its boundary): "
                                 "nothing inside it to solve for; select a larger region", what, V));
  return p;
}

}  // namespace db
