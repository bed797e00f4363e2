#include "edit/selection.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numeric>

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "edit/edit_io.h"
#include "edit/transform.h"

namespace db {

std::vector<int> select_sphere(const Mesh& mesh, const Vec3& center, double radius) {
  if (!(radius >= 0)) throw InputError(fmt::format("sphere: the radius {:g} is negative", radius));
  std::vector<int> out;
  // Compared as distances, not squares: radii and offsets beyond ~1e154 or below ~1e-154 would over- or underflow.
  for (int i = 0; i < mesh.num_vertices(); ++i)
    if ((mesh.V.row(i).transpose() - center).stableNorm() <= radius) out.push_back(i);
  return out;
}

std::vector<int> select_box(const Mesh& mesh, const Vec3& lo, const Vec3& hi) {
  static const char* const axis[] = {"x", "y", "z"};
  for (int c = 0; c < 3; ++c)
    if (lo(c) > hi(c))
      throw InputError(fmt::format("box: inverted in {} ({:g} > {:g}); give the lower corner first: "
                                   "box:x0,y0,z0,x1,y1,z1 with x0 <= x1, y0 <= y1, z0 <= z1",
                                   axis[c], lo(c), hi(c)));
  std::vector<int> out;
  for (int i = 0; i < mesh.num_vertices(); ++i) {
    const Vec3 p = mesh.V.row(i);
    if ((p.array() >= lo.array()).all() && (p.array() <= hi.array()).all()) out.push_back(i);
  }
  return out;
}

std::vector<int> select_k_ring(const Adjacency& adj, int seed, int k) {
  const int nv = adj.num_vertices();
  if (seed < 0 || seed >= nv) throw InputError(fmt::format("k-ring: seed vertex {} out of range [0, {})", seed, nv));
  if (k < 0) throw InputError(fmt::format("k-ring: k must be >= 0 (got {})", k));
  std::vector<int> dist(nv, -1);
  std::vector<int> out{seed};
  dist[seed] = 0;
  // Breadth-first: `out` doubles as the queue.
  for (std::size_t q = 0; q < out.size(); ++q) {
    const int v = out[q];
    if (dist[v] == k) continue;
    for (const int* w = adj.begin(v); w != adj.end(v); ++w)
      if (dist[*w] < 0) {
        dist[*w] = dist[v] + 1;
        out.push_back(*w);
      }
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<int> select_nearest(const Mesh& mesh, const Vec3& point, int count) {
  const int nv = mesh.num_vertices();
  if (count < 1 || count > nv)
    throw InputError(fmt::format("nearest: count {} must be in [1, {}] (the number of vertices)", count, nv));
  std::vector<std::pair<double, int>> d(nv);
  for (int i = 0; i < nv; ++i) d[i] = {(mesh.V.row(i).transpose() - point).squaredNorm(), i};
  std::nth_element(d.begin(), d.begin() + (count - 1), d.end());
  std::vector<int> out;
  out.reserve(count);
  for (int i = 0; i < count; ++i) out.push_back(d[i].second);
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<int> select_by_spec(const Mesh& mesh, const std::string& spec, const std::string& base_dir) {
  const std::string what = "selection '" + spec + "'";
  const std::size_t colon = spec.find(':');
  const std::string kind = spec.substr(0, colon);
  const std::string rest = colon == std::string::npos ? "" : spec.substr(colon + 1);
  auto as_int = [&](double v, const char* name) {
    if (v != std::floor(v)) throw InputError(fmt::format("{}: {} must be an integer", what, name));
    if (std::abs(v) > 2e9) throw InputError(fmt::format("{}: {} {:.0f} is out of range (at most 2e9)", what, name, v));
    return static_cast<int>(v);
  };
  try {
    if (spec == "all") {
      std::vector<int> out(mesh.num_vertices());
      std::iota(out.begin(), out.end(), 0);
      return out;
    }
    if (kind == "sphere" && colon != std::string::npos) {
      const auto v = parse_numbers(rest, 4, what);
      return select_sphere(mesh, Vec3(v[0], v[1], v[2]), v[3]);
    }
    if (kind == "box" && colon != std::string::npos) {
      const auto v = parse_numbers(rest, 6, what);
      return select_box(mesh, Vec3(v[0], v[1], v[2]), Vec3(v[3], v[4], v[5]));
    }
    if (kind == "kring" && colon != std::string::npos) {
      const auto v = parse_numbers(rest, 2, what);
      return select_k_ring(vertex_adjacency(mesh), as_int(v[0], "the seed"), as_int(v[1], "k"));
    }
    if (kind == "nearest" && colon != std::string::npos) {
      const auto v = parse_numbers(rest, 4, what);
      return select_nearest(mesh, Vec3(v[0], v[1], v[2]), as_int(v[3], "count"));
    }
    if (kind == "indices" && !rest.empty()) {
      namespace fs = std::filesystem;
      fs::path p(rest);
      if (p.is_relative() && !base_dir.empty()) p = fs::path(base_dir) / p;
      std::vector<int> out = read_index_list(p.string(), mesh.num_vertices());
      for (int i : out)
        if (i >= mesh.num_vertices())
          throw InputError(fmt::format("{}: vertex {} out of range [0, {})", p.string(), i, mesh.num_vertices()));
      std::sort(out.begin(), out.end());
      out.erase(std::unique(out.begin(), out.end()), out.end());
      return out;
    }
  } catch (const InputError& e) {
    const std::string msg = e.what();
    if (msg.rfind(what, 0) == 0) throw;
    throw InputError(what + ": " + msg);
  }
  throw InputError(what +
                   ": expected all | sphere:cx,cy,cz,r | box:x0,y0,z0,x1,y1,z1 | kring:v,k | nearest:x,y,z,count | "
                   "indices:FILE");
}

}  // namespace db
