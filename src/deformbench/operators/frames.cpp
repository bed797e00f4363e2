#include "operators/frames.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <fmt/format.h>

#include "solvers/base/error.h"

namespace db {

namespace {
constexpr double kPi = 3.14159265358979323846;

// Tangent component of e at a vertex with unit normal n.
inline Vec3 tangential(const Vec3& e, const Vec3& n) { return e - e.dot(n) * n; }

// An edge is usable as b1 when its tangent part is not lost in round-off against its length.
inline bool usable(const Vec3& e, const Vec3& n) { return tangential(e, n).norm() > 1e-9 * e.norm(); }

Mat3 frame_from(const Vec3& dir, const Vec3& n) {
  const Vec3 b1 = tangential(dir, n).normalized();
  Mat3 F;
  F.col(0) = b1;
  F.col(1) = n.cross(b1);  // right-handed: b1 x b2 = N
  F.col(2) = n;
  return F;
}

// Any orthonormal tangent basis at a vertex: the tensor fit is basis independent, the basis only has to exist.
void tangent_basis(const Vec3& n, Vec3& t1, Vec3& t2) {
  const Vec3 a = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  t1 = tangential(a, n).normalized();
  t2 = n.cross(t1);
}
}  // namespace

const EnumText<FrameStrategy>& enum_text(FrameStrategy) {
  static const EnumText<FrameStrategy> t{"LRI frame strategy",
                                         {{FrameStrategy::First, "first"},
                                          {FrameStrategy::Random, "random"},
                                          {FrameStrategy::HeightAngle, "height_angle"},
                                          {FrameStrategy::Curvature, "curvature"}}};
  return t;
}

const EnumText<Orthonormalization>& enum_text(Orthonormalization) {
  static const EnumText<Orthonormalization> t{
      "LRI orthonormalization", {{Orthonormalization::GramSchmidt, "gram_schmidt"}, {Orthonormalization::Polar, "polar"}}};
  return t;
}

Points vertex_normals(const Points& V, const Faces& F) {
  Points N = Points::Zero(V.rows(), 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Vec3 a = V.row(F(f, 0)).transpose(), b = V.row(F(f, 1)).transpose(), c = V.row(F(f, 2)).transpose();
    // |cross| = 2 * area, direction = unit face normal: the area weighting of eq. 3-14 comes for free.
    const Eigen::RowVector3d n = (b - a).cross(c - a).transpose();
    for (int k = 0; k < 3; ++k) N.row(F(f, k)) += n;
  }
  for (Eigen::Index i = 0; i < N.rows(); ++i) {
    const double len = N.row(i).norm();
    if (!(len > 0) || !std::isfinite(len))
      throw InputError(fmt::format("vertex {}: the area-weighted normal vanishes (degenerate or folded 1-ring)", i));
    N.row(i) /= len;
  }
  return N;
}

std::vector<CurvatureTensor> curvature_tensors(const Points& V, const Adjacency& adj, const Points& N) {
  const int n = adj.num_vertices();
  std::vector<Mat3> S(n, Mat3::Zero());  // per-vertex fits, in world coordinates (tangent tensors)
  std::vector<char> fitted(n, 0);
  std::vector<double> scale(n, 0);  // mean edge length: curvature anisotropy is judged against 1/scale
  for (int i = 0; i < n; ++i) {
    const Vec3 ni = N.row(i).transpose(), xi = V.row(i).transpose();
    Vec3 t1, t2;
    tangent_basis(ni, t1, t2);
    Eigen::Matrix3d AtA = Eigen::Matrix3d::Zero();
    Eigen::Vector3d Atb = Eigen::Vector3d::Zero();
    int rows = 0;
    for (const int* p = adj.begin(i); p != adj.end(i); ++p) {
      const Vec3 e = V.row(*p).transpose() - xi;
      const double len2 = e.squaredNorm();
      scale[i] += std::sqrt(len2);
      const double u = e.dot(t1), v = e.dot(t2), w = std::hypot(u, v);
      if (!(w > 1e-9 * std::sqrt(len2))) continue;
      const double d1 = u / w, d2 = v / w;
      // kappa(d) = L d1^2 + 2 M d1 d2 + Nn d2^2: one row of the least-squares fit per neighbour.
      const Eigen::Vector3d row(d1 * d1, 2 * d1 * d2, d2 * d2);
      const double kappa = -2.0 * e.dot(ni) / len2;
      AtA += row * row.transpose();
      Atb += row * kappa;
      ++rows;
    }
    if (adj.degree(i) > 0) scale[i] /= adj.degree(i);
    if (rows < 3) continue;
    // Collinear 1-ring directions make the 3x3 fit singular: leave the vertex unfitted then.
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(AtA);
    if (!(es.eigenvalues()(0) > 1e-10 * es.eigenvalues()(2))) continue;
    const Eigen::Vector3d c = AtA.ldlt().solve(Atb);
    Eigen::Matrix<double, 3, 2> T;
    T.col(0) = t1;
    T.col(1) = t2;
    Eigen::Matrix2d II;
    II << c(0), c(1), c(1), c(2);
    S[i] = T * II * T.transpose();
    fitted[i] = 1;
  }

  std::vector<CurvatureTensor> out(n);
  for (int i = 0; i < n; ++i) {
    const Vec3 ni = N.row(i).transpose();
    Mat3 sum = Mat3::Zero();
    int count = 0;
    auto add = [&](int j) {
      if (!fitted[j]) return;
      sum += S[j];
      ++count;
    };
    add(i);
    for (const int* p = adj.begin(i); p != adj.end(i); ++p) add(*p);
    CurvatureTensor& ct = out[i];
    if (count == 0) continue;
    const Mat3 P = Mat3::Identity() - ni * ni.transpose();
    ct.II = P * (sum / count) * P;
    ct.II = 0.5 * (ct.II + ct.II.transpose()).eval();
    Vec3 t1, t2;
    tangent_basis(ni, t1, t2);
    Eigen::Matrix<double, 3, 2> T;
    T.col(0) = t1;
    T.col(1) = t2;
    const Eigen::Matrix2d B = T.transpose() * ct.II * T;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(B);
    ct.k_min = es.eigenvalues()(0);
    ct.k_max = es.eigenvalues()(1);
    ct.dir_max = (T * es.eigenvectors().col(1)).normalized();
    // Flat or umbilic: the maximum direction is a round-off artefact, not geometry.
    const double tol = 1e-6 / std::max(scale[i], 1e-300);
    ct.defined = (ct.k_max - ct.k_min) > tol && ct.dir_max.allFinite();
  }
  return out;
}

FrameField compute_frames(const Points& V, const Adjacency& adj, const Points& N, FrameStrategy strategy,
                          unsigned seed) {
  const int n = adj.num_vertices();
  FrameField ff;
  ff.F.resize(n);
  ff.ref.assign(n, -1);
  std::mt19937 rng(seed);
  std::vector<CurvatureTensor> ct;
  if (strategy == FrameStrategy::Curvature) ct = curvature_tensors(V, adj, N);

  for (int i = 0; i < n; ++i) {
    const Vec3 ni = N.row(i).transpose(), xi = V.row(i).transpose();
    const int d = adj.degree(i);
    auto edge = [&](int t) -> Vec3 { return V.row(adj.nbr[adj.off[i] + t]).transpose() - xi; };
    // The first neighbour whose edge has a tangent part: every strategy falls back to it.
    int first_usable = -1;
    for (int t = 0; t < d && first_usable < 0; ++t)
      if (usable(edge(t), ni)) first_usable = t;
    if (first_usable < 0)
      throw InputError(fmt::format("vertex {}: no 1-ring edge has a tangent component (cannot build a frame)", i));

    int pick = -1;  // neighbour slot, or -1 for a curvature direction
    bool fallback = false;
    switch (strategy) {
      case FrameStrategy::First: pick = 0; break;
      case FrameStrategy::Random: {
        // Drawn for every vertex, usable or not, so one vertex's fallback does not reshuffle the others.
        pick = d > 0 ? static_cast<int>(rng() % static_cast<unsigned>(d)) : 0;
        break;
      }
      case FrameStrategy::HeightAngle: {
        double best = -1e300;
        for (int t = 0; t < d; ++t) {
          const Vec3 e = edge(t);
          const double c = std::clamp(e.dot(ni) / e.norm(), -1.0, 1.0);
          const double theta = std::acos(c) - kPi / 2;  // eq. 4-4: > 0 below the tangent plane
          // Ties (symmetric 1-rings) keep the lower neighbour index, independent of round-off noise.
          if (theta > best + 1e-12) {
            best = theta;
            pick = t;
          }
        }
        break;
      }
      case FrameStrategy::Curvature: {
        if (ct[i].defined) {
          Vec3 dir = ct[i].dir_max;
          // The eigenvector's sign is arbitrary: orient it along the first usable edge for determinism.
          if (dir.dot(edge(first_usable)) < 0) dir = -dir;
          if (tangential(dir, ni).norm() > 1e-9) {
            ff.F[i] = frame_from(dir, ni);
            continue;
          }
        }
        pick = first_usable;
        fallback = true;
        break;
      }
    }
    if (pick < 0 || pick >= d || !usable(edge(pick), ni)) {
      pick = first_usable;
      fallback = true;
    }
    if (fallback) ++ff.fallbacks;
    ff.ref[i] = adj.nbr[adj.off[i] + pick];
    ff.F[i] = frame_from(edge(pick), ni);
  }
  return ff;
}

std::vector<Vec3> discrete_forms(const Points& V, const Adjacency& adj, const std::vector<Mat3>& frames) {
  std::vector<Vec3> d(adj.nbr.size());
  for (int i = 0; i < adj.num_vertices(); ++i) {
    const Vec3 xi = V.row(i).transpose();
    for (int t = adj.off[i]; t < adj.off[i + 1]; ++t)
      d[t] = frames[i].transpose() * (V.row(adj.nbr[t]).transpose() - xi);
  }
  return d;
}

Mat3 orthonormalize(const Mat3& F, Orthonormalization o, int vertex) {
  const double scale = F.norm();
  auto fail = [&](const char* why) {
    throw SolverError(fmt::format("LRI: the solved frame of vertex {} is degenerate ({}); the frame system cannot "
                                  "represent this rotation field",
                                  vertex, why));
  };
  if (!(scale > 1e-14) || !F.allFinite()) fail("zero or non-finite");
  if (o == Orthonormalization::GramSchmidt) {
    Mat3 Q;
    Vec3 b1 = F.col(0);
    const double n1 = b1.norm();
    if (!(n1 > 1e-10 * scale)) fail("b1 vanished");
    Q.col(0) = b1 / n1;
    Vec3 b2 = F.col(1) - Q.col(0).dot(F.col(1)) * Q.col(0);
    const double n2 = b2.norm();
    if (!(n2 > 1e-10 * scale)) fail("b2 parallel to b1");
    Q.col(1) = b2 / n2;
    Vec3 b3 = F.col(2) - Q.col(0).dot(F.col(2)) * Q.col(0) - Q.col(1).dot(F.col(2)) * Q.col(1);
    const double n3 = b3.norm();
    if (!(n3 > 1e-10 * scale)) fail("N in the plane of b1, b2");
    Q.col(2) = b3 / n3;
    return Q;
  }
  Eigen::JacobiSVD<Mat3> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  if (!(svd.singularValues()(0) > 1e-14)) fail("zero singular values");
  Mat3 U = svd.matrixU();
  if ((U * svd.matrixV().transpose()).determinant() < 0) U.col(2) = -U.col(2);
  return U * svd.matrixV().transpose();
}

Mat3 nearest_rotation(const Mat3& M) {
  if (!M.allFinite()) throw InputError("nearest_rotation: the matrix is not finite");
  Eigen::JacobiSVD<Mat3> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const auto& s = svd.singularValues();
  if (!(s(2) > 1e-12 * s(0))) throw InputError("nearest_rotation: the linear part of the transform is singular");
  Mat3 U = svd.matrixU();
  if ((U * svd.matrixV().transpose()).determinant() < 0) U.col(2) = -U.col(2);
  return U * svd.matrixV().transpose();
}

}  // namespace db
