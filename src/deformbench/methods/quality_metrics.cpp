#include "methods/quality_metrics.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include <Eigen/SVD>

#include "solvers/base/error.h"
#include "operators/frames.h"

namespace db {
namespace {
constexpr double kDeg = 180.0 / 3.14159265358979323846;

inline Vec3 row(const Points& V, int i) { return V.row(i).transpose(); }

double angle_deg(const Vec3& a, const Vec3& b) {
  // atan2 of |a x b| and a.b keeps small angles accurate (acos loses them near 1).
  return std::atan2(a.cross(b).norm(), a.dot(b)) * kDeg;
}

void check_sizes(const Points& A, const Points& B) {
  if (A.rows() != B.rows()) throw InputError("quality metrics: the two embeddings have different vertex counts");
}
}  // namespace

DistanceStats distance_between(const Points& V, const Points& ref, double diag) {
  check_sizes(V, ref);
  DistanceStats s;
  if (V.rows() == 0 || !(diag > 0)) return s;
  double sum = 0;
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    const double d = (V.row(i) - ref.row(i)).norm();
    sum += d * d;
    s.max = std::max(s.max, d);
  }
  s.rms = std::sqrt(sum / V.rows()) / diag;
  s.max /= diag;
  return s;
}

double edge_length_distortion(const Points& V0, const Points& V, const Adjacency& adj) {
  check_sizes(V0, V);
  double sum = 0;
  std::size_t m = 0;
  for (int i = 0; i < adj.num_vertices(); ++i)
    for (const int* p = adj.begin(i); p != adj.end(i); ++p) {
      if (*p < i) continue;  // each undirected edge once
      const double l0 = (V0.row(*p) - V0.row(i)).norm(), l = (V.row(*p) - V.row(i)).norm();
      if (!(l0 > 0)) continue;
      sum += ((l - l0) / l0) * ((l - l0) / l0);
      ++m;
    }
  return m ? std::sqrt(sum / m) : 0.0;
}

std::vector<Mat3> best_fit_rotations(const Points& V0, const Points& V, const Adjacency& adj) {
  check_sizes(V0, V);
  std::vector<Mat3> R(adj.num_vertices(), Mat3::Identity());
  for (int i = 0; i < adj.num_vertices(); ++i) {
    Mat3 S = Mat3::Zero();  // sum_j e'_ij e_ij^T: R = argmax tr(R^T S)
    for (const int* p = adj.begin(i); p != adj.end(i); ++p)
      S += (row(V, *p) - row(V, i)) * (row(V0, *p) - row(V0, i)).transpose();
    Eigen::JacobiSVD<Mat3> svd(S, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Mat3 U = svd.matrixU();
    if ((U * svd.matrixV().transpose()).determinant() < 0) U.col(2) = -U.col(2);
    R[i] = U * svd.matrixV().transpose();
  }
  return R;
}

double arap_energy(const Points& V0, const Points& V, const Adjacency& adj) {
  const auto R = best_fit_rotations(V0, V, adj);
  double e = 0, ref = 0;
  for (int i = 0; i < adj.num_vertices(); ++i)
    for (const int* p = adj.begin(i); p != adj.end(i); ++p) {
      const Vec3 e0 = row(V0, *p) - row(V0, i);
      e += ((row(V, *p) - row(V, i)) - R[i] * e0).squaredNorm();
      ref += e0.squaredNorm();
    }
  return ref > 0 ? e / ref : 0.0;
}

AngleStats normal_deviation(const Points& V, const Points& ref, const Faces& F) {
  check_sizes(V, ref);
  const Points N = vertex_normals(V, F), Nr = vertex_normals(ref, F);
  AngleStats s;
  for (Eigen::Index i = 0; i < N.rows(); ++i) {
    const double a = angle_deg(row(N, static_cast<int>(i)), row(Nr, static_cast<int>(i)));
    s.mean_deg += a;
    s.max_deg = std::max(s.max_deg, a);
  }
  if (N.rows() > 0) s.mean_deg /= N.rows();
  return s;
}

AngleStats local_normal_deviation(const Points& V0, const Points& V, const Faces& F, const Adjacency& adj) {
  const Points N0 = vertex_normals(V0, F), N = vertex_normals(V, F);
  const auto R = best_fit_rotations(V0, V, adj);
  AngleStats s;
  for (int i = 0; i < adj.num_vertices(); ++i) {
    const double a = angle_deg(row(N, i), R[i] * row(N0, i));
    s.mean_deg += a;
    s.max_deg = std::max(s.max_deg, a);
  }
  if (adj.num_vertices() > 0) s.mean_deg /= adj.num_vertices();
  return s;
}

double lri_detail_error(const Points& V0, const Points& V, const Faces& F, const Adjacency& adj) {
  check_sizes(V0, V);
  const auto f0 = compute_frames(V0, adj, vertex_normals(V0, F), FrameStrategy::First);
  const auto f1 = compute_frames(V, adj, vertex_normals(V, F), FrameStrategy::First);
  const auto d0 = discrete_forms(V0, adj, f0.F), d1 = discrete_forms(V, adj, f1.F);
  double e = 0, ref = 0;
  for (std::size_t k = 0; k < d0.size(); ++k) {
    e += (d1[k] - d0[k]).squaredNorm();
    ref += d0[k].squaredNorm();
  }
  return ref > 0 ? std::sqrt(e / ref) : 0.0;
}

bool is_closed(const Faces& F) {
  std::map<std::pair<int, int>, int> uses;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  if (uses.empty()) return false;
  for (const auto& kv : uses)
    if (kv.second != 2) return false;
  return true;
}

double signed_volume(const Points& V, const Faces& F) {
  if (V.rows() == 0) return 0;
  // About the centroid: the same volume for a closed surface, without the round-off of far-away coordinates.
  const Vec3 c = V.colwise().mean().transpose();
  double v = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    v += (row(V, F(f, 0)) - c).dot((row(V, F(f, 1)) - c).cross(row(V, F(f, 2)) - c));
  return v / 6.0;
}

std::optional<double> volume_change(const Points& V0, const Points& V, const Faces& F) {
  check_sizes(V0, V);
  if (!is_closed(F)) return std::nullopt;
  const double v0 = signed_volume(V0, F);
  if (!(std::abs(v0) > 0)) return std::nullopt;
  return (signed_volume(V, F) - v0) / std::abs(v0);
}

}  // namespace db
