#include "methods/scaled_edit.h"

#include <cmath>

#include <fmt/format.h>

#include "mesh/subdivision.h"
#include "solvers/base/error.h"

namespace db {
namespace {

//! The roles after one round of Loop subdivision of `coarse` into `fine`: the first vertices keep theirs; every new
//! vertex lies on an edge of the coarse mesh, and its only coarse neighbours are that edge's two ends.
std::vector<Role> subdivided_roles(const Mesh& coarse, const Mesh& fine, const std::vector<Role>& roles) {
  const int nc = coarse.num_vertices();
  std::vector<Role> out(static_cast<std::size_t>(fine.num_vertices()), Role::Free);
  std::copy(roles.begin(), roles.end(), out.begin());
  std::vector<int> first(out.size(), -1), second(out.size(), -1);  // a new vertex's coarse neighbours
  for (int f = 0; f < fine.num_faces(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int a = fine.F(f, c), b = fine.F(f, (c + 1) % 3);
      const int v = a >= nc ? a : b, w = a >= nc ? b : a;
      if (v < nc || w >= nc) continue;  // not a new-to-coarse edge
      if (first[v] < 0 || first[v] == w) first[v] = w;
      else second[v] = w;
    }
  for (std::size_t v = static_cast<std::size_t>(nc); v < out.size(); ++v) {
    if (first[v] < 0 || second[v] < 0) continue;
    const Role a = roles[static_cast<std::size_t>(first[v])], b = roles[static_cast<std::size_t>(second[v])];
    out[v] = a == b ? a : Role::Free;
  }
  return out;
}

}  // namespace

int scale_levels(int num_vertices, double scale) {
  if (!(scale >= 1)) throw InputError(fmt::format("scale {} is below 1", scale));
  int levels = static_cast<int>(std::floor(std::log(scale) / std::log(4.0) + 0.5));
  while (levels > 0 && num_vertices * std::pow(4.0, levels) > kMaxScaledVertices) --levels;
  return levels;
}

ScaledEdit scale_edit(const Mesh& mesh, const Edit& edit, double scale) {
  ScaledEdit s;
  s.levels = scale_levels(mesh.num_vertices(), scale);
  s.residual = scale / std::pow(4.0, s.levels);
  s.mesh = mesh;
  s.edit.name = edit.name;
  s.edit.roles = edit.roles;
  s.edit.transform = edit.transform;
  for (int l = 0; l < s.levels; ++l) {
    Mesh fine = loop_subdivide(s.mesh, 1);
    s.edit.roles = subdivided_roles(s.mesh, fine, s.edit.roles);
    s.mesh = std::move(fine);
  }
  s.mesh.name = s.levels > 0 ? fmt::format("{}_loop{}", mesh.name, s.levels) : mesh.name;
  return s;
}

}  // namespace db
