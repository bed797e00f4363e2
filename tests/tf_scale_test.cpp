// TF with normalized scale (--tf-scale normalized, issue 17): the second pass keeps the rotations of TF's fitted
// similarities and drops their scale.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <Eigen/Dense>

#include "solvers/base/error.h"
#include "edit/transform.h"
#include "mesh/procedural.h"
#include "methods/deformer.h"
#include "methods/quality_metrics.h"
#include "exact_deformation.h"
#include "test_util.h"

namespace db {
namespace {

DeformOptions tf(bool normalized, Build build = Build::Structured) {
  DeformOptions o;
  o.method = Method::Tf;
  o.tf_scale = normalized ? TfScale::Normalized : TfScale::Free;
  o.build = build;
  return o;
}

TEST(TfScale, RigidTranslationEqualsPlainTf) {
  // Every constraint translated: TF's fitted similarities are the identity, so the second pass changes nothing.
  const Mesh m = tube();
  for (bool all_handle : {true, false}) {
    const Edit e = tube_edit(m, all_handle);
    const Mat4 T = all_handle ? translation(Vec3(0.3, -1.2, 2.5)) : Mat4::Identity();
    // Both against the analytic answer (the translated mesh), not against each other: they round differently.
    const Points plain = make_deformer(m, e, tf(false))->deform(T);
    const Points normalized = make_deformer(m, e, tf(true))->deform(T);
    EXPECT_WITHIN(normalized_rel(m, plain, transformed(m.V, T)), deformation_bound(m, e, tf(false))) << all_handle;
    EXPECT_LT(rel_rms(normalized, transformed(m.V, T)), 1e-9) << all_handle;
  }
}

TEST(TfScale, RotatedEditDriftsLessInScaleThanPlainTf) {
  // A 60-degree bend of a tube: the ideal keeps every edge; TF's linearized similarities stretch and shrink.
  const Mesh m = make_cylinder(30, 16, 1.0, 10.0);
  Edit e;
  e.roles.assign(m.num_vertices(), Role::Free);
  double zf = -1e300, zh = 1e300;
  for (int v = 0; v < m.num_vertices(); ++v) {
    if (m.V(v, 2) <= 2 + 1e-9) e.roles[v] = Role::Fixed, zf = std::max(zf, m.V(v, 2));
    if (m.V(v, 2) >= 8 - 1e-9) e.roles[v] = Role::Handle, zh = std::min(zh, m.V(v, 2));
  }
  const double angle = 60 * 3.14159265358979323846 / 180;
  const Mat4 T = bend_transform(angle, zf, zh);
  const Points ideal = ideal_bend(m.V, angle, zf, zh);
  const Adjacency adj = vertex_adjacency(m);
  const Points plain = make_deformer(m, e, tf(false))->deform(T);
  const Points normalized = make_deformer(m, e, tf(true))->deform(T);
  const double edge_plain = edge_length_distortion(m.V, plain, adj);
  const double edge_norm = edge_length_distortion(m.V, normalized, adj);
  std::printf("60-degree bend: edge-length distortion tf %.4f, normalized %.4f; RMS to ideal tf %.4f, normalized %.4f\n",
              edge_plain, edge_norm, rel_rms(plain, ideal), rel_rms(normalized, ideal));
  EXPECT_LT(edge_norm, edge_plain);
  EXPECT_LT(rel_rms(normalized, ideal), rel_rms(plain, ideal));
}

// The second pass by dense linear algebra, written independently of the library: the similarity s I + [h]x + t
// fitted to each 1-ring of `V1` by QR, its rotation by SVD (polar), the uniform Laplacian as a dense matrix and the
// constrained least-squares solve by QR.
Points dense_second_pass(const Mesh& m, const Edit& e, const Mat4& T, const Points& V1, double& fit_condition) {
  const int n = m.num_vertices();
  const Adjacency adj = vertex_adjacency(m);
  Eigen::MatrixXd L = Eigen::MatrixXd::Identity(n, n);
  for (int i = 0; i < n; ++i)
    for (const int* p = adj.begin(i); p != adj.end(i); ++p) L(i, *p) = -1.0 / adj.degree(i);
  const Eigen::MatrixXd delta = L * m.V;
  Eigen::MatrixXd target(n, 3);
  for (int i = 0; i < n; ++i) {
    std::vector<int> ring(adj.begin(i), adj.end(i));
    ring.push_back(i);
    Eigen::MatrixXd A(3 * ring.size(), 7);
    Eigen::VectorXd b(3 * ring.size());
    for (std::size_t k = 0; k < ring.size(); ++k) {
      const double x = m.V(ring[k], 0), y = m.V(ring[k], 1), z = m.V(ring[k], 2);
      A.middleRows(3 * k, 3) << x, 0, z, -y, 1, 0, 0, y, -z, 0, x, 0, 1, 0, z, y, -x, 0, 0, 0, 1;
      b.segment(3 * k, 3) = V1.row(ring[k]).transpose();
    }
    const Eigen::VectorXd p = A.colPivHouseholderQr().solve(b);
    const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(A).singularValues();
    fit_condition = std::max(fit_condition, sv(0) / sv(sv.size() - 1));
    Mat3 S;
    S << p(0), -p(3), p(2), p(3), p(0), -p(1), -p(2), p(1), p(0);
    const Eigen::JacobiSVD<Mat3> svd(S, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Mat3 R = svd.matrixU() * svd.matrixV().transpose();
    EXPECT_GT(R.determinant(), 0);  // s > 0 here: the polar factor is a rotation
    target.row(i) = (R * delta.row(i).transpose()).transpose();
  }
  std::vector<int> free, hard;
  for (int v = 0; v < n; ++v) (e.roles[v] == Role::Free ? free : hard).push_back(v);
  Eigen::MatrixXd Lu(n, free.size()), Lh(n, hard.size()), xh(hard.size(), 3);
  for (std::size_t k = 0; k < free.size(); ++k) Lu.col(k) = L.col(free[k]);
  for (std::size_t k = 0; k < hard.size(); ++k) {
    Lh.col(k) = L.col(hard[k]);
    const Vec3 p = m.V.row(hard[k]).transpose();
    xh.row(k) = (e.roles[hard[k]] == Role::Handle ? apply(T, p) : p).transpose();
  }
  const Eigen::MatrixXd xu = Lu.colPivHouseholderQr().solve(target - Lh * xh);
  Points out(n, 3);
  for (std::size_t k = 0; k < free.size(); ++k) out.row(free[k]) = xu.row(k);
  for (std::size_t k = 0; k < hard.size(); ++k) out.row(hard[k]) = xh.row(k);
  return out;
}

TEST(TfScale, MatchesADenseReference) {
  const Mesh m = make_cylinder(8, 10, 1.0, 3.0);
  const Edit e = tube_edit(m);
  const Mat4 T = rotation_about_axis(Vec3(1, 0, 0), 40, Vec3(0, 0, 3)) * translation(Vec3(0.2, 0, 0));
  const Points V1 = make_deformer(m, e, tf(false))->deform(T);
  double fit_condition = 1;
  const Points reference = dense_second_pass(m, e, T, V1, fit_condition);
  EXPECT_GT(rel_rms(reference, V1), 1e-4);  // the second pass does change the result
  // Both sides' error, first order: the first pass's (deformation_bound) moves each 1-ring fit by up to its
  // least-squares condition times that; the rotations enter the second pass's right-hand side, whose solve multiplies
  // their error by cond(K) of the LAP system and adds its own rounding. The reference's QR solves are as well
  // conditioned (cond(Lu) = sqrt(cond(K))): twice the bound covers both.
  DeformOptions lap = tf(true);
  lap.method = Method::Lap;
  const double c_lap = system_condition(m, e, lap);
  const double tol = 2 * (exact::solve_bound(c_lap) + c_lap * fit_condition * deformation_bound(m, e, tf(false)));
  for (Build b : {Build::Structured, Build::Naive, Build::Dense}) {
    const Points out = make_deformer(m, e, tf(true, b))->deform(T);
    EXPECT_WITHIN(normalized_rel(m, out, reference), tol) << to_string(b);
  }
}

TEST(TfScale, SoftConstraintsAndFramesWork) {
  // Soft constraints take the same second pass (their targets enter both systems); frames reuse both factors.
  const Mesh m = tube();
  const Edit e = tube_edit(m);
  DeformOptions o = tf(true);
  o.constraints = ConstraintMode::Soft;
  o.soft_weight = 1e4;
  const Mat4 T = rotation_about_axis(Vec3(1, 0, 0), 30, Vec3(0, 0, 4));
  auto d = make_deformer(m, e, o);
  const Points first = d->deform(Mat4::Identity());
  EXPECT_LT(rel_rms(first, m.V), 1e-9);
  const Points soft = d->deform(T);
  const Points hard = make_deformer(m, e, tf(true))->deform(T);
  EXPECT_LT(rel_rms(soft, hard), 1e-3);
  EXPECT_EQ(d->systems().size(), 2u);
}

TEST(TfScale, OtherMethodsRefuseIt) {
  const Mesh m = tube();
  const Edit e = tube_edit(m);
  for (const char* method : {"lap", "lri"}) {
    DeformOptions o = tf(true);
    o.method = parse_enum<Method>(method);
    EXPECT_THROW(make_deformer(m, e, o), UsageError) << method;  // options that do not go together
  }
}

TEST(TfScale, HandleFramesRefuseIt) {
  // The second pass rotates by fitted rotations: a frame is not affine in the handle map.
  const Mesh m = tube();
  const Edit e = tube_edit(m);
  DeformOptions o = tf(true);
  o.frame_mode = FrameMode::Handle;
  EXPECT_THROW(make_deformer(m, e, o), UsageError);
  EXPECT_THROW(make_deformer(m, e, tf(true))->precompute_handle_frames(), InputError);
}

}  // namespace
}  // namespace db
