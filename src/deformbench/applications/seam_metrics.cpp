#include "applications/seam_metrics.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace db {
namespace {

std::pair<int, int> key(int a, int b) { return {std::min(a, b), std::max(a, b)}; }

}  // namespace

SeamAngles dihedral_angles(const Mesh& mesh, const std::vector<std::pair<int, int>>& edges) {
  std::map<std::pair<int, int>, std::vector<Vec3>> normals;  // the unit normals of each edge's faces
  for (const auto& [a, b] : edges) normals[key(a, b)];
  for (int f = 0; f < mesh.num_faces(); ++f)
    for (int c = 0; c < 3; ++c) {
      const auto it = normals.find(key(mesh.F(f, c), mesh.F(f, (c + 1) % 3)));
      if (it == normals.end()) continue;
      const Vec3 a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)), d = mesh.V.row(mesh.F(f, 2));
      it->second.push_back((b - a).cross(d - a).normalized());
    }
  SeamAngles s;
  for (const auto& [edge, n] : normals) {
    if (n.size() != 2) continue;
    const double deg = std::atan2(n[0].cross(n[1]).norm(), n[0].dot(n[1])) * 180.0 / M_PI;
    s.max_deg = std::max(s.max_deg, deg);
    s.mean_deg += deg;
    ++s.edges;
  }
  if (s.edges > 0) s.mean_deg /= s.edges;
  return s;
}

SeamAngles seam_angles(const Mesh& mesh, const DiskPatch& patch) {
  std::vector<std::pair<int, int>> edges;
  const std::size_t m = patch.boundary.size();
  for (std::size_t k = 0; k < m; ++k)
    edges.emplace_back(patch.parent[patch.boundary[k]], patch.parent[patch.boundary[(k + 1) % m]]);
  return dihedral_angles(mesh, edges);
}

SeamAngles band_angles(const Mesh& mesh, int first_face) {
  std::vector<std::pair<int, int>> edges;
  for (int f = first_face; f < mesh.num_faces(); ++f)
    for (int c = 0; c < 3; ++c) edges.emplace_back(mesh.F(f, c), mesh.F(f, (c + 1) % 3));
  return dihedral_angles(mesh, edges);
}

}  // namespace db
