// Local frames, discrete forms, curvature tensors and orthonormalization of LRI (operators/frames.h).
#include <gtest/gtest.h>

#include <cmath>

#include "solvers/base/error.h"
#include "mesh/mesh.h"
#include "mesh/procedural.h"
#include "operators/frames.h"
#include "test_util.h"

namespace db {
namespace {

bool interior_ring(const Mesh& m, int v) {
  const double z = m.V(v, 2);
  return z > 1e-9 && z < 4.0 - 1e-9;
}

void expect_orthonormal_right_handed(const Mat3& F, double tol = 1e-12) {
  EXPECT_LT((F.transpose() * F - Mat3::Identity()).norm(), tol);
  EXPECT_NEAR(F.determinant(), 1.0, tol);
}

Mat3 rot_z(double a) {
  Mat3 Z;
  Z << std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a), 0, 0, 0, 1;
  return Z;
}

TEST(Frames, ParseNamesRoundTripAndRejectUnknown) {
  for (const char* s : {"first", "random", "height_angle", "curvature"})
    EXPECT_EQ(to_string(parse_enum<FrameStrategy>(s)), s);
  for (const char* s : {"gram_schmidt", "polar"}) EXPECT_EQ(to_string(parse_enum<Orthonormalization>(s)), s);
  EXPECT_THROW(parse_enum<FrameStrategy>("principal"), InputError);
  EXPECT_THROW(parse_enum<FrameStrategy>(""), InputError);
  EXPECT_THROW(parse_enum<Orthonormalization>("qr"), InputError);
}

TEST(Frames, NormalsOfATubePointOutwards) {
  const Mesh m = tube();
  const Points N = vertex_normals(m.V, m.F);
  for (int v = 0; v < m.num_vertices(); ++v) {
    EXPECT_NEAR(N.row(v).norm(), 1.0, 1e-12);
    if (!interior_ring(m, v)) continue;
    const Vec3 radial(m.V(v, 0), m.V(v, 1), 0.0);
    EXPECT_GT(N.row(v).dot(radial.normalized().transpose()), 0.999) << "vertex " << v;
  }
}

TEST(Frames, NormalsOfAFlatPlaneAreExactlyUp) {
  const Mesh m = make_bumpy_plane(6, 5, 2.0, 0.0, 1);
  const Points N = vertex_normals(m.V, m.F);
  for (int v = 0; v < m.num_vertices(); ++v) EXPECT_LT((N.row(v) - Eigen::RowVector3d(0, 0, 1)).norm(), 1e-14);
}

TEST(Frames, DegenerateNormalIsInputError) {
  Mesh m;
  m.V.resize(3, 3);
  m.V << 0, 0, 0, 1, 0, 0, 2, 0, 0;  // collinear: zero-area face
  m.F.resize(1, 3);
  m.F << 0, 1, 2;
  EXPECT_THROW(vertex_normals(m.V, m.F), InputError);
}

class EveryStrategy : public ::testing::TestWithParam<std::string> {};

TEST_P(EveryStrategy, FramesAreOrthonormalWithTheVertexNormal) {
  const Mesh m = tube();
  const Adjacency adj = vertex_adjacency(m);
  const Points N = vertex_normals(m.V, m.F);
  const FrameField ff = compute_frames(m.V, adj, N, parse_enum<FrameStrategy>(GetParam()), 7);
  ASSERT_EQ(static_cast<int>(ff.F.size()), m.num_vertices());
  for (int v = 0; v < m.num_vertices(); ++v) {
    expect_orthonormal_right_handed(ff.F[v]);
    EXPECT_LT((ff.F[v].col(2) - N.row(v).transpose()).norm(), 1e-14);
    if (ff.ref[v] >= 0) {
      // b1 is the tangent projection of the edge to the reference neighbour.
      const Vec3 e = (m.V.row(ff.ref[v]) - m.V.row(v)).transpose();
      EXPECT_GT(e.dot(ff.F[v].col(0)), 0.0);
      EXPECT_NEAR(e.dot(ff.F[v].col(1)), 0.0, 1e-12);
    }
  }
}

TEST_P(EveryStrategy, DiscreteFormsAndConnectionReconstructTheMesh) {
  const Mesh m = tube();
  const Adjacency adj = vertex_adjacency(m);
  const FrameField ff = compute_frames(m.V, adj, vertex_normals(m.V, m.F), parse_enum<FrameStrategy>(GetParam()), 3);
  const auto d = discrete_forms(m.V, adj, ff.F);
  ASSERT_EQ(d.size(), adj.nbr.size());
  for (int i = 0; i < m.num_vertices(); ++i)
    for (int s = adj.off[i]; s < adj.off[i + 1]; ++s) {
      const int j = adj.nbr[s];
      const Vec3 e = (m.V.row(j) - m.V.row(i)).transpose();
      EXPECT_LT((ff.F[i] * d[s] - e).norm(), 1e-14);  // eq. 3-18 holds exactly on the rest mesh
      EXPECT_LT((ff.F[i] * frame_connection(ff.F[i], ff.F[j]) - ff.F[j]).norm(), 1e-14);  // eq. 3-17
    }
}

INSTANTIATE_TEST_SUITE_P(Lri, EveryStrategy, ::testing::Values("first", "random", "height_angle", "curvature"));

TEST(Frames, FirstTakesTheLowestNeighbour) {
  const Mesh m = tube();
  const Adjacency adj = vertex_adjacency(m);
  const FrameField ff = compute_frames(m.V, adj, vertex_normals(m.V, m.F), FrameStrategy::First);
  for (int v = 0; v < m.num_vertices(); ++v) EXPECT_EQ(ff.ref[v], adj.nbr[adj.off[v]]);
  EXPECT_EQ(ff.fallbacks, 0);
}

TEST(Frames, RandomIsReproducibleAndSeeded) {
  const Mesh m = tube();
  const Adjacency adj = vertex_adjacency(m);
  const Points N = vertex_normals(m.V, m.F);
  const auto a = compute_frames(m.V, adj, N, FrameStrategy::Random, 11);
  const auto b = compute_frames(m.V, adj, N, FrameStrategy::Random, 11);
  const auto c = compute_frames(m.V, adj, N, FrameStrategy::Random, 12);
  const auto f = compute_frames(m.V, adj, N, FrameStrategy::First);
  EXPECT_EQ(a.ref, b.ref);
  EXPECT_NE(a.ref, c.ref);
  EXPECT_NE(a.ref, f.ref);
}

TEST(Frames, HeightAngleAndCurvaturePickTheCircumferenceOfATube) {
  // On a tube the ring neighbours leave the tangent plane most (eq. 4-4) and the circumference is the maximum
  // principal direction: both strategies put b1 across the axis; "first" does not.
  const Mesh m = tube();
  const Adjacency adj = vertex_adjacency(m);
  const Points N = vertex_normals(m.V, m.F);
  const auto h = compute_frames(m.V, adj, N, FrameStrategy::HeightAngle);
  const auto c = compute_frames(m.V, adj, N, FrameStrategy::Curvature);
  const auto f = compute_frames(m.V, adj, N, FrameStrategy::First);
  double first_axial = 0;
  for (int v = 0; v < m.num_vertices(); ++v) {
    if (!interior_ring(m, v)) continue;
    EXPECT_LT(std::abs(h.F[v](2, 0)), 1e-12) << "vertex " << v;
    EXPECT_EQ(std::abs(h.ref[v] - v) == 1 || std::abs(h.ref[v] - v) == 15, true) << "vertex " << v;
    EXPECT_LT(std::abs(c.F[v](2, 0)), 0.1) << "vertex " << v;
    first_axial = std::max(first_axial, std::abs(f.F[v](2, 0)));
  }
  EXPECT_GT(first_axial, 0.5);
  EXPECT_EQ(c.fallbacks, 0);
}

TEST(Frames, CurvatureTensorOfATube) {
  const double r = 2.0;
  const Mesh m = make_cylinder(30, 48, r, 6.0);
  const Adjacency adj = vertex_adjacency(m);
  const Points N = vertex_normals(m.V, m.F);
  const auto ct = curvature_tensors(m.V, adj, N);
  for (int v = 0; v < m.num_vertices(); ++v) {
    const double z = m.V(v, 2);
    if (z < 0.5 || z > 5.5) continue;
    ASSERT_TRUE(ct[v].defined) << "vertex " << v;
    EXPECT_NEAR(ct[v].k_max, 1.0 / r, 0.05 / r) << "vertex " << v;
    EXPECT_NEAR(ct[v].k_min, 0.0, 0.05 / r) << "vertex " << v;
    EXPECT_LT(std::abs(ct[v].dir_max.z()), 0.05) << "vertex " << v;
    EXPECT_LT((ct[v].II * N.row(v).transpose()).norm(), 1e-12);  // a tangent tensor
  }
}

TEST(Frames, CurvatureFallsBackOnAFlatPlane) {
  const Mesh m = make_bumpy_plane(6, 6, 2.0, 0.0, 1);
  const Adjacency adj = vertex_adjacency(m);
  const Points N = vertex_normals(m.V, m.F);
  const auto ct = curvature_tensors(m.V, adj, N);
  for (const auto& t : ct) EXPECT_FALSE(t.defined);
  const auto ff = compute_frames(m.V, adj, N, FrameStrategy::Curvature);
  EXPECT_EQ(ff.fallbacks, m.num_vertices());
  const auto first = compute_frames(m.V, adj, N, FrameStrategy::First);
  EXPECT_EQ(ff.ref, first.ref);  // the first usable neighbour is the first one on a plane
}

TEST(Frames, OrthonormalizeKeepsRotationsAndProjectsOthers) {
  const Mat3 R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  for (auto o : {Orthonormalization::GramSchmidt, Orthonormalization::Polar}) {
    EXPECT_LT((orthonormalize(R, o) - R).norm(), 1e-14);
    EXPECT_LT((orthonormalize(0.3 * R, o) - R).norm(), 1e-14);  // shrunken frames (least squares) come back
  }
  Mat3 A;
  A << 0.9, 0.2, -0.1, 0.05, 0.7, 0.3, 0.1, -0.2, 0.8;
  for (auto o : {Orthonormalization::GramSchmidt, Orthonormalization::Polar})
    expect_orthonormal_right_handed(orthonormalize(A, o), 1e-13);
  // Gram-Schmidt keeps b1's direction; polar does not in general.
  EXPECT_LT((orthonormalize(A, Orthonormalization::GramSchmidt).col(0) - A.col(0).normalized()).norm(), 1e-14);
}

TEST(Frames, PolarCommutesWithATangentRotationGramSchmidtDoesNot) {
  // The algebra behind the frame-strategy verdict: another b1 is F Z with Z a rotation about the normal;
  // polar(F Z) = polar(F) Z for any F, while Gram-Schmidt only commutes when F is already orthonormal.
  Mat3 A;
  A << 0.9, 0.2, -0.1, 0.05, 0.7, 0.3, 0.1, -0.2, 0.8;
  const Mat3 Z = rot_z(1.1);
  const Mat3 P = orthonormalize(A, Orthonormalization::Polar), PZ = orthonormalize(A * Z, Orthonormalization::Polar);
  EXPECT_LT((PZ - P * Z).norm(), 1e-13);
  const Mat3 G = orthonormalize(A, Orthonormalization::GramSchmidt);
  const Mat3 GZ = orthonormalize(A * Z, Orthonormalization::GramSchmidt);
  EXPECT_GT((GZ - G * Z).norm(), 1e-3);
}

TEST(Frames, DegenerateSolvedFrameIsSolverError) {
  Mat3 A = Mat3::Zero();
  EXPECT_THROW(orthonormalize(A, Orthonormalization::Polar, 5), SolverError);
  A.col(1) = Vec3(0, 1, 0);
  A.col(2) = Vec3(0, 0, 1);
  EXPECT_THROW(orthonormalize(A, Orthonormalization::GramSchmidt, 5), SolverError);  // b1 vanished
  A.col(0) = Vec3(0, 2, 0);
  EXPECT_THROW(orthonormalize(A, Orthonormalization::GramSchmidt, 5), SolverError);  // b2 parallel to b1
}

TEST(Frames, NearestRotation) {
  const Mat3 R = Eigen::AngleAxisd(2.5, Vec3(0, 1, 1).normalized()).toRotationMatrix();
  EXPECT_LT((nearest_rotation(2.0 * R) - R).norm(), 1e-13);
  EXPECT_THROW(nearest_rotation(Mat3::Zero()), InputError);
}

}  // namespace
}  // namespace db
