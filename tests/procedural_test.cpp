// Procedural shapes, their analytic ideal deformations, and Loop subdivision.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <utility>

#include <Eigen/Geometry>

#include "solvers/base/error.h"
#include "mesh/mesh.h"
#include "mesh/mesh_io.h"
#include "mesh/procedural.h"
#include "mesh/subdivision.h"

namespace {

using namespace db;
constexpr double kPi = 3.14159265358979323846;

// Number of faces on each undirected edge.
std::map<std::pair<int, int>, int> edge_faces(const Mesh& m) {
  std::map<std::pair<int, int>, int> e;
  for (int f = 0; f < m.num_faces(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int a = m.F(f, c), b = m.F(f, (c + 1) % 3);
      ++e[{std::min(a, b), std::max(a, b)}];
    }
  return e;
}

// Signed volume by the divergence theorem; positive for a closed surface with outward normals.
double signed_volume(const Mesh& m) {
  double v = 0;
  for (int f = 0; f < m.num_faces(); ++f) {
    const Vec3 a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
    v += a.dot(b.cross(c)) / 6.0;
  }
  return v;
}

Vec3 face_normal(const Mesh& m, int f) {
  const Vec3 a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
  return (b - a).cross(c - a);
}

TEST(Procedural, CylinderCountsRadiusAndOrientation) {
  const int rings = 6, segments = 9;
  const double r = 0.7, h = 3.0;
  const Mesh m = make_cylinder(rings, segments, r, h);
  EXPECT_NO_THROW(validate_mesh(m));
  EXPECT_EQ(m.num_vertices(), rings * segments);
  EXPECT_EQ(m.num_faces(), 2 * (rings - 1) * segments);
  for (int i = 0; i < m.num_vertices(); ++i) EXPECT_NEAR(std::hypot(m.V(i, 0), m.V(i, 1)), r, 1e-14);
  EXPECT_DOUBLE_EQ(m.V.col(2).minCoeff(), 0.0);
  EXPECT_DOUBLE_EQ(m.V.col(2).maxCoeff(), h);
  int boundary = 0;
  for (const auto& [e, n] : edge_faces(m)) boundary += n == 1;
  EXPECT_EQ(boundary, 2 * segments);  // two open rims
  for (int f = 0; f < m.num_faces(); ++f) {
    const Vec3 c = (m.V.row(m.F(f, 0)) + m.V.row(m.F(f, 1)) + m.V.row(m.F(f, 2))) / 3.0;
    EXPECT_GT(face_normal(m, f).dot(Vec3(c(0), c(1), 0)), 0) << "face " << f << " points inward";
  }
}

TEST(Procedural, BarIsClosedOutwardAndHasTheBoxVolume) {
  const int nx = 3, ny = 2, nz = 5;
  const double sx = 1.5, sy = 0.5, sz = 4.0;
  const Mesh m = make_bar(nx, ny, nz, sx, sy, sz);
  EXPECT_NO_THROW(validate_mesh(m));
  EXPECT_EQ(m.num_vertices(), (nx + 1) * (ny + 1) * (nz + 1) - (nx - 1) * (ny - 1) * (nz - 1));
  EXPECT_EQ(m.num_faces(), 4 * (nx * ny + ny * nz + nz * nx));
  for (const auto& [e, n] : edge_faces(m)) EXPECT_EQ(n, 2) << "edge " << e.first << "-" << e.second;
  EXPECT_NEAR(signed_volume(m), sx * sy * sz, 1e-12);
  // Euler characteristic of a sphere.
  EXPECT_EQ(m.num_vertices() - static_cast<int>(edge_faces(m).size()) + m.num_faces(), 2);
  EXPECT_NEAR(m.V.col(2).minCoeff(), 0.0, 0);
  EXPECT_NEAR(m.V.col(0).maxCoeff() - m.V.col(0).minCoeff(), sx, 1e-15);
}

TEST(Procedural, SingleCellBar) {
  const Mesh m = make_bar(1, 1, 1, 1, 1, 1);
  EXPECT_NO_THROW(validate_mesh(m));
  EXPECT_EQ(m.num_vertices(), 8);
  EXPECT_EQ(m.num_faces(), 12);
}

TEST(Procedural, BumpyPlane) {
  const int nx = 8, ny = 6, bumps = 2;
  const double size = 2.0, bump = 0.1;
  const Mesh m = make_bumpy_plane(nx, ny, size, bump, bumps);
  EXPECT_NO_THROW(validate_mesh(m));
  EXPECT_EQ(m.num_vertices(), (nx + 1) * (ny + 1));
  EXPECT_EQ(m.num_faces(), 2 * nx * ny);
  EXPECT_LE(m.V.col(2).cwiseAbs().maxCoeff(), bump + 1e-15);
  EXPECT_GT(m.V.col(2).cwiseAbs().maxCoeff(), 0.5 * bump);  // the bumps are there
  for (int f = 0; f < m.num_faces(); ++f) EXPECT_GT(face_normal(m, f)(2), 0) << "face " << f;
  EXPECT_NEAR(m.V.col(0).maxCoeff() - m.V.col(0).minCoeff(), size, 1e-15);
}

TEST(Procedural, BadParametersAreInputErrors) {
  EXPECT_THROW(make_cylinder(1, 8, 1, 1), InputError);
  EXPECT_THROW(make_cylinder(3, 2, 1, 1), InputError);
  EXPECT_THROW(make_bar(0, 1, 1, 1, 1, 1), InputError);
  EXPECT_THROW(make_bar(1, 1, 1, 1, -1, 1), InputError);
  EXPECT_THROW(make_bumpy_plane(0, 3, 1, 0.1, 1), InputError);
  EXPECT_THROW(ideal_bend(Points(0, 3), 1.0, 2.0, 1.0), InputError);
  EXPECT_THROW(ideal_twist(Points(0, 3), 1.0, 1.0, 1.0), InputError);
}

TEST(IdealBend, PreservesLengthsAlongTheNeutralAxis) {
  const int rings = 41, segments = 8;  // even: vertices j = 0 and j = segments/2 lie on the neutral plane y = 0
  const double h = 10.0, z0 = 2.0, z1 = 8.0, angle = 2 * kPi / 3;
  const Mesh m = make_cylinder(rings, segments, 1.0, h);
  const Points B = ideal_bend(m.V, angle, z0, z1);
  for (int j : {0, segments / 2}) {
    double len0 = 0, len1 = 0;
    for (int i = 0; i + 1 < rings; ++i) {
      const int a = i * segments + j, b = (i + 1) * segments + j;
      ASSERT_NEAR(m.V(a, 1), 0.0, 1e-15);
      const double l0 = (m.V.row(b) - m.V.row(a)).norm(), l1 = (B.row(b) - B.row(a)).norm();
      // A chord of the arc is shorter than the arc: relative error bounded by theta^2/24 per edge.
      const double dtheta = angle * (h / (rings - 1)) / (z1 - z0);
      EXPECT_NEAR(l1, l0, l0 * dtheta * dtheta / 24 + 1e-12) << "edge " << a << "-" << b;
      len0 += l0;
      len1 += l1;
    }
    EXPECT_NEAR(len1, len0, 1e-3 * len0);
  }
  // The end of the bent region turns by the full angle: an axis-parallel edge above z1 now points along
  // (0, sin angle, cos angle).
  const int a = (rings - 2) * segments, b = (rings - 1) * segments;
  const Vec3 d = (B.row(b) - B.row(a)).normalized();
  EXPECT_NEAR(d.dot(Vec3(0, std::sin(angle), std::cos(angle))), 1.0, 1e-12);
}

TEST(IdealBend, UnchangedBelowRigidAboveIdentityAtZeroAngle) {
  const Mesh m = make_cylinder(21, 6, 0.5, 4.0);
  const double z0 = 1.0, z1 = 3.0;
  const Points B = ideal_bend(m.V, 1.3, z0, z1);
  std::vector<int> above;
  for (int i = 0; i < m.num_vertices(); ++i) {
    if (m.V(i, 2) < z0) {
      EXPECT_EQ(B.row(i), m.V.row(i));
    }
    if (m.V(i, 2) > z1) above.push_back(i);
    EXPECT_EQ(B(i, 0), m.V(i, 0));  // bending about x leaves x alone
  }
  ASSERT_GE(above.size(), 2u);
  for (int p : above)
    for (int q : above) EXPECT_NEAR((B.row(p) - B.row(q)).norm(), (m.V.row(p) - m.V.row(q)).norm(), 1e-12);
  EXPECT_EQ(ideal_bend(m.V, 0.0, z0, z1), m.V);
}

TEST(IdealTwist, PreservesAxisDistanceAndHeight) {
  const Mesh m = make_bar(3, 3, 20, 1.0, 1.0, 10.0);
  const double z0 = 2.0, z1 = 8.0, angle = 3 * kPi / 4;
  const Points T = ideal_twist(m.V, angle, z0, z1);
  for (int i = 0; i < m.num_vertices(); ++i) {
    EXPECT_NEAR(std::hypot(T(i, 0), T(i, 1)), std::hypot(m.V(i, 0), m.V(i, 1)), 1e-14);
    EXPECT_EQ(T(i, 2), m.V(i, 2));
    const double t = std::clamp((m.V(i, 2) - z0) / (z1 - z0), 0.0, 1.0);
    const Vec3 expect = Eigen::AngleAxisd(angle * t, Vec3::UnitZ()) * Vec3(m.V.row(i));
    EXPECT_NEAR((Vec3(T.row(i)) - expect).norm(), 0.0, 1e-14);
    if (m.V(i, 2) <= z0) {
      EXPECT_NEAR((T.row(i) - m.V.row(i)).norm(), 0.0, 1e-15);
    }
  }
}

// The handle transforms of the bend and twist cases: beyond z1 they move a point where the ideal does.
TEST(IdealBendAndTwist, HandleTransformsMatchTheIdealBeyondZ1) {
  const Mesh m = make_cylinder(21, 6, 0.5, 4.0);
  const double z0 = 1.0, z1 = 3.0;
  for (double angle : {0.0, 0.7, kPi}) {
    const Points B = ideal_bend(m.V, angle, z0, z1), T = ideal_twist(m.V, angle, z0, z1);
    const Mat4 Tb = bend_transform(angle, z0, z1), Tt = twist_transform(angle);
    for (int i = 0; i < m.num_vertices(); ++i) {
      if (m.V(i, 2) < z1) continue;
      const Eigen::Vector4d p(m.V(i, 0), m.V(i, 1), m.V(i, 2), 1.0);
      EXPECT_NEAR(((Tb * p).head<3>() - Vec3(B.row(i))).norm(), 0.0, 1e-12) << angle;
      EXPECT_NEAR(((Tt * p).head<3>() - Vec3(T.row(i))).norm(), 0.0, 1e-12) << angle;
    }
  }
  EXPECT_THROW(bend_transform(1.0, 2.0, 2.0), InputError);
}

TEST(LoopSubdivide, CountsManifoldAndDeterministic) {
  for (const Mesh& m : {make_bar(2, 2, 3, 1, 1, 2), make_cylinder(4, 6, 1, 2), make_bumpy_plane(3, 3, 1, 0.1, 1)}) {
    SCOPED_TRACE(m.name);
    const int edges = static_cast<int>(edge_faces(m).size());
    const Mesh s = loop_subdivide(m, 1);
    EXPECT_EQ(s.num_vertices(), m.num_vertices() + edges);
    EXPECT_EQ(s.num_faces(), 4 * m.num_faces());
    EXPECT_NO_THROW(validate_mesh(s));
    EXPECT_EQ(s.name, m.name + "_loop1");
    const Mesh s2 = loop_subdivide(m, 2);
    EXPECT_EQ(s2.num_vertices(), s.num_vertices() + static_cast<int>(edge_faces(s).size()));
    EXPECT_NO_THROW(validate_mesh(s2));
    const Mesh again = loop_subdivide(m, 2);
    EXPECT_EQ(again.V, s2.V);
    EXPECT_EQ(again.F, s2.F);
  }
}

TEST(LoopSubdivide, ClosedSurfaceStaysClosedAndOriented) {
  const Mesh s = loop_subdivide(make_bar(2, 2, 2, 1, 1, 1), 2);
  for (const auto& [e, n] : edge_faces(s)) EXPECT_EQ(n, 2);
  EXPECT_GT(signed_volume(s), 0);  // orientation kept (the volume shrinks but stays positive)
}

TEST(LoopSubdivide, ZeroLevelsIsACopyAndBadInputThrows) {
  const Mesh m = make_cylinder(3, 5, 1, 1);
  const Mesh s = loop_subdivide(m, 0);
  EXPECT_EQ(s.V, m.V);
  EXPECT_EQ(s.F, m.F);
  EXPECT_THROW(loop_subdivide(m, -1), InputError);
  Mesh bad;
  bad.V.resize(5, 3);
  bad.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1;
  bad.F.resize(3, 3);
  bad.F << 0, 1, 2, 1, 0, 3, 0, 1, 4;  // three faces on edge 0-1
  EXPECT_THROW(loop_subdivide(bad, 1), InputError);
}

TEST(LoopSubdivide, ArmadilloLevelOne) {
  const std::string p = DEFORMBENCH_SOURCE_DIR "/data/meshes/armadillo.off";
  ASSERT_TRUE(std::filesystem::exists(p)) << p << " is missing: run scripts/data.sh (./run test does)";
  const Mesh m = read_mesh(p);
  const Mesh s = loop_subdivide(m, 1);
  EXPECT_EQ(s.num_vertices(), m.num_vertices() + static_cast<int>(edge_faces(m).size()));
  EXPECT_NO_THROW(validate_mesh(s));
}

}  // namespace
