#include "mesh/procedural.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "solvers/base/error.h"

namespace db {

namespace {

constexpr double kPi = 3.14159265358979323846;

void require(bool ok, const std::string& msg) {
  if (!ok) throw InputError(msg);
}

void add_quad(Faces& F, int& f, int a, int b, int c, int d) {
  // a b c d counter-clockwise: two triangles sharing the a-c diagonal.
  F.row(f++) << a, b, c;
  F.row(f++) << a, c, d;
}

}  // namespace

Mesh make_cylinder(int rings, int segments, double radius, double height) {
  require(rings >= 2 && segments >= 3,
          fmt::format("make_cylinder: need rings >= 2 and segments >= 3 (got {}, {})", rings, segments));
  require(radius > 0 && height > 0, "make_cylinder: radius and height must be positive");
  Mesh m;
  m.name = fmt::format("cylinder_{}x{}", rings, segments);
  m.V.resize(static_cast<Eigen::Index>(rings) * segments, 3);
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double a = 2 * kPi * j / segments;
      m.V.row(i * segments + j) << radius * std::cos(a), radius * std::sin(a), height * i / (rings - 1);
    }
  m.F.resize(2 * static_cast<Eigen::Index>(rings - 1) * segments, 3);
  int f = 0;
  for (int i = 0; i + 1 < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const int jn = (j + 1) % segments;
      // Around +theta then up +z: (theta x z) points outward.
      add_quad(m.F, f, i * segments + j, i * segments + jn, (i + 1) * segments + jn, (i + 1) * segments + j);
    }
  return m;
}

Mesh make_bar(int nx, int ny, int nz, double sx, double sy, double sz) {
  require(nx >= 1 && ny >= 1 && nz >= 1, fmt::format("make_bar: need nx, ny, nz >= 1 (got {}, {}, {})", nx, ny, nz));
  require(sx > 0 && sy > 0 && sz > 0, "make_bar: sizes must be positive");
  const int n[3] = {nx, ny, nz};
  const double lo[3] = {-sx / 2, -sy / 2, 0}, size[3] = {sx, sy, sz};
  // Lattice points on the box surface get ids in lattice order (z slowest), so the numbering is deterministic.
  const auto lattice = [&](int i, int j, int k) { return (static_cast<long>(k) * (ny + 1) + j) * (nx + 1) + i; };
  std::vector<int> id(static_cast<std::size_t>(nx + 1) * (ny + 1) * (nz + 1), -1);
  std::vector<double> xyz;
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        if (i != 0 && i != nx && j != 0 && j != ny && k != 0 && k != nz) continue;
        id[lattice(i, j, k)] = static_cast<int>(xyz.size() / 3);
        const int c[3] = {i, j, k};
        for (int a = 0; a < 3; ++a) xyz.push_back(lo[a] + size[a] * c[a] / n[a]);
      }
  Mesh m;
  m.name = fmt::format("bar_{}x{}x{}", nx, ny, nz);
  m.V = Eigen::Map<const Points>(xyz.data(), static_cast<Eigen::Index>(xyz.size() / 3), 3);
  m.F.resize(4 * (static_cast<Eigen::Index>(nx) * ny + static_cast<Eigen::Index>(ny) * nz +
                  static_cast<Eigen::Index>(nz) * nx),
             3);
  int f = 0;
  for (int a = 0; a < 3; ++a) {
    // Side with normal +-e_a; (u, v) cyclic after a, so e_u x e_v = e_a.
    const int u = (a + 1) % 3, v = (a + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      for (int q = 0; q < n[v]; ++q)
        for (int p = 0; p < n[u]; ++p) {
          int corner[4];
          const int du[4] = {0, 1, 1, 0}, dv[4] = {0, 0, 1, 1};
          for (int c = 0; c < 4; ++c) {
            int ijk[3];
            ijk[a] = side == 0 ? 0 : n[a];
            ijk[u] = p + du[c];
            ijk[v] = q + dv[c];
            corner[c] = id[lattice(ijk[0], ijk[1], ijk[2])];
          }
          if (side == 1) add_quad(m.F, f, corner[0], corner[1], corner[2], corner[3]);
          else add_quad(m.F, f, corner[0], corner[3], corner[2], corner[1]);
        }
    }
  }
  return m;
}

Mesh make_bumpy_plane(int nx, int ny, double size, double bump_height, int bumps) {
  require(nx >= 1 && ny >= 1, fmt::format("make_bumpy_plane: need nx, ny >= 1 (got {}, {})", nx, ny));
  require(size > 0 && bumps >= 0, "make_bumpy_plane: size must be positive and bumps non-negative");
  Mesh m;
  m.name = fmt::format("plane_{}x{}", nx, ny);
  m.V.resize(static_cast<Eigen::Index>(nx + 1) * (ny + 1), 3);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const double u = static_cast<double>(i) / nx, v = static_cast<double>(j) / ny;
      m.V.row(j * (nx + 1) + i) << size * (u - 0.5), size * (v - 0.5),
          bump_height * std::sin(2 * kPi * bumps * u) * std::sin(2 * kPi * bumps * v);
    }
  m.F.resize(2 * static_cast<Eigen::Index>(nx) * ny, 3);
  int f = 0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int a = j * (nx + 1) + i;
      add_quad(m.F, f, a, a + 1, a + nx + 2, a + nx + 1);
    }
  return m;
}

Points ideal_bend(const Points& V, double angle_rad, double z0, double z1) {
  require(z1 > z0, fmt::format("ideal_bend: need z1 > z0 (got {}, {})", z0, z1));
  Points out = V;
  if (angle_rad == 0) return out;
  const double L = z1 - z0, R = L / angle_rad;
  const double ca = std::cos(angle_rad), sa = std::sin(angle_rad);
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    const double y = V(i, 1), z = V(i, 2);
    if (z < z0) continue;
    if (z <= z1) {
      const double t = angle_rad * (z - z0) / L;
      out(i, 1) = R - (R - y) * std::cos(t);
      out(i, 2) = z0 + (R - y) * std::sin(t);
    } else {
      // End frame: e_y -> (cos a, -sin a), e_z -> (sin a, cos a) in the (y, z) plane, origin at the arc end.
      const double s = z - z1;
      out(i, 1) = R - (R - y) * ca + s * sa;
      out(i, 2) = z0 + (R - y) * sa + s * ca;
    }
  }
  return out;
}

Points ideal_twist(const Points& V, double angle_rad, double z0, double z1) {
  require(z1 > z0, fmt::format("ideal_twist: need z1 > z0 (got {}, {})", z0, z1));
  Points out = V;
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    const double t = std::clamp((V(i, 2) - z0) / (z1 - z0), 0.0, 1.0);
    const double c = std::cos(angle_rad * t), s = std::sin(angle_rad * t);
    out(i, 0) = c * V(i, 0) - s * V(i, 1);
    out(i, 1) = s * V(i, 0) + c * V(i, 1);
  }
  return out;
}

Mat4 bend_transform(double angle_rad, double z0, double z1) {
  require(z1 > z0, fmt::format("bend_transform: need z1 > z0 (got {}, {})", z0, z1));
  Mat4 T = Mat4::Identity();
  if (angle_rad == 0) return T;
  const double R = (z1 - z0) / angle_rad, c = std::cos(angle_rad), s = std::sin(angle_rad);
  T.block<2, 2>(1, 1) << c, s, -s, c;
  T(1, 3) = -z1 * s + R * (1 - c);
  T(2, 3) = -z1 * c + z0 + R * s;
  return T;
}

Mat4 twist_transform(double angle_rad) {
  Mat4 T = Mat4::Identity();
  T.topLeftCorner<3, 3>() = Eigen::AngleAxisd(angle_rad, Vec3::UnitZ()).toRotationMatrix();
  return T;
}

}  // namespace db
