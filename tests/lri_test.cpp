// LRI deformation (methods/lri.h): reconstruction, rigid-motion invariance, frame strategies, the structured
// build against the naive one, the frame-strategy algebra, bad input; and the quality metrics it is judged by.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <tuple>

#include <Eigen/SVD>

#include "solvers/base/error.h"
#include "edit/transform.h"
#include "mesh/procedural.h"
#include "methods/deformer.h"
#include "methods/lri.h"
#include "methods/quality_metrics.h"
#include "exact_deformation.h"
#include "test_util.h"

namespace db {
namespace {

constexpr double kPi = 3.14159265358979323846;

DeformOptions lri(const std::string& frames, const std::string& ortho, ConstraintMode mode = ConstraintMode::Hard) {
  DeformOptions o;
  o.method = Method::Lri;
  o.lri_frames = parse_enum<FrameStrategy>(frames);
  o.lri_orthonormalize = parse_enum<Orthonormalization>(ortho);
  o.constraints = mode;
  return o;
}

Mat4 some_rigid_motion() {
  Mat4 T = rotation_about_axis(Vec3(1, 2, 3), 70.0, Vec3(0.3, -0.2, 1.0));
  T.topRightCorner<3, 1>() += Vec3(0.5, -1.0, 2.0);
  return T;
}

using Config = std::tuple<std::string, std::string>;
class EveryConfig : public ::testing::TestWithParam<Config> {};

TEST_P(EveryConfig, IdentityEditReproducesTheMesh) {
  const auto& [frames, ortho] = GetParam();
  const Mesh m = tube();
  for (auto mode : {ConstraintMode::Hard, ConstraintMode::Soft}) {
    auto d = make_deformer(m, tube_edit(m), lri(frames, ortho, mode));
    EXPECT_LT(rel_max(d->deform(Mat4::Identity()), m.V), 1e-8) << to_string(mode);
  }
}

TEST_P(EveryConfig, RotatingEveryConstraintRotatesTheResult) {
  const auto& [frames, ortho] = GetParam();
  const Mesh m = tube();
  const Mat4 T = some_rigid_motion();
  for (auto mode : {ConstraintMode::Hard, ConstraintMode::Soft}) {
    auto d = make_deformer(m, tube_edit(m, true), lri(frames, ortho, mode));
    EXPECT_LT(rel_max(d->deform(T), transformed(m.V, T)), 1e-8) << to_string(mode);
  }
}

TEST_P(EveryConfig, BendKeepsConstraintsAndBeatsLap) {
  const auto& [frames, ortho] = GetParam();
  const Mesh m = tube();
  const Edit e = tube_edit(m);
  const double z0 = 4.0 / 11, z1 = 4.0 - 4.0 / 11, a = kPi / 2;  // last fixed ring, first handle ring
  const Mat4 T = bend_transform(a, z0, z1);
  const Points ideal = ideal_bend(m.V, a, z0, z1);
  auto d = make_deformer(m, e, lri(frames, ortho));
  const Points out = d->deform(T);
  ASSERT_TRUE(out.allFinite());
  for (int v = 0; v < m.num_vertices(); ++v) {
    if (e.roles[v] == Role::Handle) {
      EXPECT_LT((out.row(v) - ideal.row(v)).norm(), 1e-12);
    } else if (e.roles[v] == Role::Fixed) {
      EXPECT_LT((out.row(v) - m.V.row(v)).norm(), 1e-12);
    }
  }
  DeformOptions lap;
  lap.method = Method::Lap;
  const Points lap_out = make_deformer(m, e, lap)->deform(T);
  const double diag = bbox_diagonal(m.V);
  EXPECT_LT(distance_between(out, ideal, diag).rms, distance_between(lap_out, ideal, diag).rms);
  EXPECT_LT(edge_length_distortion(m.V, out, vertex_adjacency(m)),
            edge_length_distortion(m.V, lap_out, vertex_adjacency(m)));
}

INSTANTIATE_TEST_SUITE_P(Lri, EveryConfig,
                         ::testing::Combine(::testing::Values("first", "random", "height_angle", "curvature"),
                                            ::testing::Values("gram_schmidt", "polar")));

TEST(Lri, ReportsTwoFactoredSystems) {
  const Mesh m = tube();
  const Edit e = tube_edit(m);
  auto d = make_deformer(m, e, lri("first", "polar"));
  ASSERT_EQ(d->systems().size(), 2u);
  const std::size_t nu = static_cast<std::size_t>(e.count(Role::Free));
  EXPECT_EQ(d->systems()[0].name, "frames");
  EXPECT_EQ(d->systems()[0].n, 3 * nu);
  EXPECT_EQ(d->systems()[1].name, "positions");
  EXPECT_EQ(d->systems()[1].n, nu);
  for (const auto& s : d->systems()) {
    EXPECT_GT(s.nnz, 0u);
    EXPECT_GT(s.factor.nnz_factor, 0u);
  }
  EXPECT_GT(d->matrix_bytes(), 0u);
  d->deform(rotation_about_axis(Vec3(1, 0, 0), 30.0));
  EXPECT_GE(d->times().solve, 0.0);
}

TEST(Lri, StructuredAndNaiveBuildsAgree) {
  const Mesh m = tube();
  const Edit e = tube_edit(m);
  for (auto mode : {ConstraintMode::Hard, ConstraintMode::Soft}) {
    DeformOptions o = lri("height_angle", "gram_schmidt", mode);
    o.soft_weight = 3.0;
    LriDeformer s(m, e, o);
    o.build = Build::Naive;
    LriDeformer n(m, e, o);
    for (auto pair : {std::make_pair(&s.frame_system(), &n.frame_system()),
                      std::make_pair(&s.position_system(), &n.position_system())}) {
      EXPECT_LT((DenseMat(pair.first->K) - DenseMat(pair.second->K)).norm(), 1e-12);
      EXPECT_LT((DenseMat(pair.first->C) - DenseMat(pair.second->C)).norm(), 1e-12);
    }
    // Each build against the exact deformation (exact_deformation.h): the two round differently.
    const Mat4 T = rotation_about_axis(Vec3(1, 0, 0), 120.0, Vec3(0, 1, 3.5));
    const Points ref = make_deformer(m, e, exact_options(o))->deform(T);
    const double tol = deformation_bound(m, e, o);
    EXPECT_WITHIN(normalized_rel(m, s.deform(T), ref), tol) << to_string(mode) << " structured";
    EXPECT_WITHIN(normalized_rel(m, n.deform(T), ref), tol) << to_string(mode) << " naive";
  }
}

TEST(Lri, FrameSystemIsTheConnectionLaplacian) {
  // sum over both directions of ||u_j - R_ij^T u_i||^2: diagonal blocks 2 deg(i) I, off-diagonal -2 R_ij.
  const Mesh m = tube();
  Edit e = tube_edit(m);
  LriDeformer d(m, e, lri("first", "polar", ConstraintMode::Soft));
  const DenseMat K = DenseMat(d.frame_system().K).selfadjointView<Eigen::Upper>();
  const Adjacency adj = vertex_adjacency(m);
  const auto& F = d.rest_frames().F;
  const int i = 40;
  const double w2 = e.roles[i] == Role::Free ? 0.0 : 1.0;
  EXPECT_LT((K.block<3, 3>(3 * i, 3 * i) - (2.0 * adj.degree(i) + w2) * Mat3::Identity()).norm(), 1e-12);
  for (const int* p = adj.begin(i); p != adj.end(i); ++p)
    EXPECT_LT((K.block<3, 3>(3 * i, 3 * *p) + 2.0 * F[i].transpose() * F[*p]).norm(), 1e-12);
}

TEST(Lri, PolarResultDoesNotDependOnTheFrameStrategy) {
  // Rotating every frame about its normal (another b1) maps the least-squares frame solution F' to F' Z_i
  // exactly, and polar(F' Z) = polar(F') Z, so the positions agree to round-off; Gram-Schmidt need not. Round-off
  // here: each strategy's frames and positions are within the bound of their systems' conditioning of the exact
  // ones (exact_deformation.h), so two strategies within twice that of each other.
  const Mesh m = make_cylinder(16, 16, 1.0, 4.0);
  const Edit e = tube_edit(m);
  const Mat4 T = rotation_about_axis(Vec3(1, 0, 0), -150.0, Vec3(0, 1.5, 3.5));
  LriDeformer a(m, e, lri("first", "polar"));
  const Points pa = a.deform(T);
  const double positions_tol = 2 * deformation_bound(m, e, lri("first", "polar"));
  // The frame system's condition does not depend on the strategy (another b1 is a block-orthogonal similarity).
  const double frames_tol = 2 * exact::solve_bound(exact::condition_number(a.frame_system().K));
  double frames_norm = 0;
  for (int v = 0; v < m.num_vertices(); ++v) frames_norm += a.solved_frames_raw()[v].squaredNorm();
  frames_norm = std::sqrt(frames_norm);
  for (const char* s : {"random", "height_angle", "curvature"}) {
    LriDeformer b(m, e, lri(s, "polar"));
    const Points pb = b.deform(T);
    EXPECT_WITHIN(normalized_rel(m, pb, pa), positions_tol) << s;
    double frames_diff = 0;  // the frames stacked, as the frame system's unknowns
    for (int v = 0; v < m.num_vertices(); ++v) {
      const Mat3 Z = a.rest_frames().F[v].transpose() * b.rest_frames().F[v];  // rotation about the normal
      frames_diff += (a.solved_frames_raw()[v] * Z - b.solved_frames_raw()[v]).squaredNorm();
    }
    EXPECT_WITHIN(std::sqrt(frames_diff) / frames_norm, frames_tol) << s;
  }
}

TEST(Lri, FrameSolveIsAHarmonicBlendOfRotations) {
  // F'_i = W_i F_i with W_i = I + h_i (R - I), h harmonic (0 fixed, 1 handle), whatever the rest frames are.
  const Mesh m = make_cylinder(14, 12, 1.0, 4.0);
  const Edit e = tube_edit(m);
  const Mat4 T = rotation_about_axis(Vec3(1, 0.3, 0), 100.0, Vec3(0, 1.5, 3.5));
  const Mat3 D = T.topLeftCorner<3, 3>() - Mat3::Identity();
  const Adjacency adj = vertex_adjacency(m);
  std::vector<double> h0;
  for (const char* s : {"first", "curvature"}) {
    LriDeformer d(m, e, lri(s, "gram_schmidt"));
    d.deform(T);
    // The solved frames stacked lie within the frame system's solve bound (relative) of the exact ones; an entry
    // of W - I, and so h (W - I over D), within that times the stacked frames' norm.
    double frames_norm = 0;
    for (int v = 0; v < m.num_vertices(); ++v) frames_norm += d.solved_frames_raw()[v].squaredNorm();
    const double tol = exact::solve_bound(exact::condition_number(d.frame_system().K)) * std::sqrt(frames_norm);
    std::vector<double> h(m.num_vertices());
    for (int v = 0; v < m.num_vertices(); ++v) {
      const Mat3 W = d.solved_frames_raw()[v] * d.rest_frames().F[v].transpose();
      h[v] = (W - Mat3::Identity()).cwiseProduct(D).sum() / D.squaredNorm();
      EXPECT_WITHIN((W - Mat3::Identity() - h[v] * D).norm(), 2 * tol) << s << " vertex " << v;
      EXPECT_GT(h[v], -tol / D.norm());
      EXPECT_LT(h[v], 1 + tol / D.norm());
    }
    for (int v = 0; v < m.num_vertices(); ++v) {
      if (e.roles[v] != Role::Free) continue;
      double mean = 0;
      for (const int* p = adj.begin(v); p != adj.end(v); ++p) mean += h[*p];
      EXPECT_WITHIN(std::abs(h[v] - mean / adj.degree(v)), 2 * tol / D.norm()) << "vertex " << v;  // harmonic
    }
    if (h0.empty()) h0 = h;
    for (int v = 0; v < m.num_vertices(); ++v) EXPECT_WITHIN(std::abs(h[v] - h0[v]), 2 * tol / D.norm()) << v;
  }
}

TEST(Lri, HalfTurnCollapsesTheMiddleFrames) {
  // At exactly 180 degrees W = aa^T + (1 - 2h)(I - aa^T) is singular on h = 1/2: a symmetric tube puts a ring there,
  // Gram-Schmidt loses b1 (SolverError), polar still returns a (round-off chosen) rotation.
  const Mesh m = make_cylinder(13, 12, 1.0, 4.0);  // middle ring at z = 2, between the constrained ends
  Edit e = tube_edit(m);
  const Mat4 T = bend_transform(kPi, 4.0 / 12, 4.0 - 4.0 / 12);
  EXPECT_THROW(LriDeformer(m, e, lri("first", "gram_schmidt")).deform(T), SolverError);
  LriDeformer p(m, e, lri("first", "polar"));
  EXPECT_TRUE(p.deform(T).allFinite());
  double smin = 1;
  for (const Mat3& F : p.solved_frames_raw()) {
    const Eigen::JacobiSVD<Mat3> svd(F);
    const Vec3 sv = svd.singularValues();
    smin = std::min(smin, sv(2));
  }
  EXPECT_LT(smin, 1e-9);
}

TEST(Lri, ScalingHandleRotatesFramesOnly) {
  const Mesh m = tube();
  const Edit e = tube_edit(m, true);
  Mat4 S = Mat4::Identity();
  S.topLeftCorner<3, 3>() *= 1.5;  // frames see the identity rotation; positions the scaling
  auto d = make_deformer(m, e, lri("first", "polar"));
  const Points out = d->deform(S);
  ASSERT_TRUE(out.allFinite());
  EXPECT_LT((out.row(0) - 1.5 * m.V.row(0)).norm(), 1e-12);
}

TEST(Lri, UncoordinatedControlKeepsTheRestFrames) {
  const Mesh m = tube();
  const Edit e = tube_edit(m);
  const Mat4 T = bend_transform(kPi / 2, 4.0 / 11, 4.0 - 4.0 / 11);
  DeformOptions o = lri("first", "gram_schmidt");
  o.lri_frame_control = FrameControl::Uncoordinated;
  auto d = make_deformer(m, e, o);
  const auto& lri_d = dynamic_cast<const LriDeformer&>(*d);
  const Points out = d->deform(T);
  ASSERT_TRUE(out.allFinite());
  // Every frame constraint at rest: the frame solve returns the rest frames, so nothing turns.
  double frame_dev = 0;
  for (int v = 0; v < m.num_vertices(); ++v)
    frame_dev = std::max(frame_dev, (lri_d.solved_frames_raw()[v] - lri_d.rest_frames().F[v]).norm());
  EXPECT_LT(frame_dev, 1e-9);
  // The positions are still constrained: the handle lands where the transform puts it.
  const Points moved = transformed(m.V, T);
  for (int v = 0; v < m.num_vertices(); ++v) {
    if (e.roles[v] == Role::Handle) {
      EXPECT_LT((out.row(v) - moved.row(v)).norm(), 1e-12);
    }
  }
  // ... and the result is not the coordinated one (the bend's frames would turn by up to 90 degrees).
  const Points coordinated = make_deformer(m, e, lri("first", "gram_schmidt"))->deform(T);
  EXPECT_GT(rel_max(out, coordinated), 1e-2);
  // A translation has no rotation to coordinate: both controls give the exact (coordinated) deformation.
  Mat4 shift = Mat4::Identity();
  shift.topRightCorner<3, 1>() = Vec3(0.3, -0.2, 0.5);
  const Points ref = make_deformer(m, e, exact_options(lri("first", "gram_schmidt")))->deform(shift);
  const double tol = deformation_bound(m, e, lri("first", "gram_schmidt"));
  EXPECT_WITHIN(normalized_rel(m, d->deform(shift), ref), tol) << "uncoordinated";
  EXPECT_WITHIN(normalized_rel(m, make_deformer(m, e, lri("first", "gram_schmidt"))->deform(shift), ref), tol)
      << "coordinated";
}

TEST(Lri, BadInput) {
  const Mesh m = tube();
  const Edit e = tube_edit(m);
  EXPECT_THROW(make_deformer(m, e, lri("principal", "polar")), InputError);
  EXPECT_THROW(make_deformer(m, e, lri("first", "qr")), InputError);
  EXPECT_THROW(make_lri_deformer(m, e, lri("", "polar")), InputError);
  DeformOptions dense = lri("first", "polar");
  dense.build = Build::Dense;
  EXPECT_THROW(make_deformer(m, e, dense), UsageError);  // options that do not go together
  // A free region that touches no constraint is singular in both systems.
  Edit floating = e;
  for (auto& r : floating.roles) r = Role::Free;
  floating.roles[0] = Role::Handle;
  Mesh two = m;  // a second, unconstrained tube next to the first
  two.V.resize(2 * m.num_vertices(), 3);
  two.V << m.V, (m.V.rowwise() + Eigen::RowVector3d(5, 0, 0));
  two.F.resize(2 * m.num_faces(), 3);
  two.F << m.F, (m.F.array() + m.num_vertices()).matrix();
  floating.roles.resize(two.num_vertices(), Role::Free);
  EXPECT_THROW(make_deformer(two, floating, lri("first", "polar")), InputError);
  // A singular handle transform has no rotation for the frames.
  auto d = make_deformer(m, e, lri("first", "polar"));
  Mat4 flat = Mat4::Identity();
  flat(2, 2) = 0;
  EXPECT_THROW(d->deform(flat), InputError);
  DeformOptions budget = lri("first", "polar");
  budget.memory_budget = 1000;
  EXPECT_THROW(make_deformer(m, e, budget), BudgetError);
}

TEST(QualityMetrics, ZeroForRigidMotions) {
  const Mesh m = tube();
  const Adjacency adj = vertex_adjacency(m);
  const Points R = transformed(m.V, some_rigid_motion());
  EXPECT_LT(edge_length_distortion(m.V, R, adj), 1e-14);
  EXPECT_LT(arap_energy(m.V, R, adj), 1e-24);
  EXPECT_LT(lri_detail_error(m.V, R, m.F, adj), 1e-12);
  EXPECT_LT(local_normal_deviation(m.V, R, m.F, adj).max_deg, 1e-5);
  EXPECT_GT(normal_deviation(R, m.V, m.F).max_deg, 10.0);  // but the normals did turn
  const DistanceStats s = distance_between(m.V, m.V, 1.0);
  EXPECT_EQ(s.rms, 0.0);
  EXPECT_EQ(s.max, 0.0);
}

TEST(QualityMetrics, MeasureStretchingAndVolume) {
  const Mesh bar = make_bar(2, 3, 4, 1.0, 2.0, 3.0);
  ASSERT_TRUE(is_closed(bar.F));
  EXPECT_NEAR(signed_volume(bar.V, bar.F), 6.0, 1e-12);
  Points stretched = bar.V;
  stretched.col(2) *= 2.0;
  ASSERT_TRUE(volume_change(bar.V, stretched, bar.F).has_value());
  EXPECT_NEAR(*volume_change(bar.V, stretched, bar.F), 1.0, 1e-12);
  const Adjacency adj = vertex_adjacency(bar);
  EXPECT_GT(edge_length_distortion(bar.V, stretched, adj), 0.1);
  EXPECT_GT(arap_energy(bar.V, stretched, adj), 0.01);
  EXPECT_GT(lri_detail_error(bar.V, stretched, bar.F, adj), 0.1);
  const Mesh open = tube();
  EXPECT_FALSE(is_closed(open.F));
  EXPECT_FALSE(volume_change(open.V, open.V, open.F).has_value());
  const Points moved = (bar.V.rowwise() + Eigen::RowVector3d(0, 0, 1)).eval();
  const DistanceStats d = distance_between(moved, bar.V, 2.0);
  EXPECT_NEAR(d.rms, 0.5, 1e-14);
  EXPECT_NEAR(d.max, 0.5, 1e-14);
}

}  // namespace
}  // namespace db
