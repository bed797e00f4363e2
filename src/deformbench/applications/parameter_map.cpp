#include "applications/parameter_map.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "solvers/base/error.h"

namespace db {
namespace {

using Vec2 = Eigen::Vector2d;

// Barycentric coordinates of p in triangle (a, b, c); a degenerate triangle gives non-finite values.
void barycentric(const Vec2& p, const Vec2& a, const Vec2& b, const Vec2& c, double w[3]) {
  const Vec2 v0 = b - a, v1 = c - a, v2 = p - a;
  const double den = v0.x() * v1.y() - v1.x() * v0.y();
  w[1] = (v2.x() * v1.y() - v1.x() * v2.y()) / den;
  w[2] = (v0.x() * v2.y() - v2.x() * v0.y()) / den;
  w[0] = 1.0 - w[1] - w[2];
}

class TriangleGrid {
 public:
  TriangleGrid(const UV& uv, const Faces& F) : uv_(uv), F_(F) {
    g_ = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(F.rows()))));
    lo_ = Vec2(uv.col(0).minCoeff(), uv.col(1).minCoeff());
    const Vec2 hi(uv.col(0).maxCoeff(), uv.col(1).maxCoeff());
    cell_ = std::max((hi - lo_).maxCoeff() / g_, 1e-300);
    cells_.resize(static_cast<std::size_t>(g_) * g_);
    for (int f = 0; f < F.rows(); ++f) {
      Vec2 a = corner(f, 0), b = a;
      for (int c = 1; c < 3; ++c) {
        a = a.cwiseMin(corner(f, c));
        b = b.cwiseMax(corner(f, c));
      }
      for (int y = clamp_cell(a.y(), 1); y <= clamp_cell(b.y(), 1); ++y)
        for (int x = clamp_cell(a.x(), 0); x <= clamp_cell(b.x(), 0); ++x) cells_[y * g_ + x].push_back(f);
    }
  }

  // The face whose smallest barycentric coordinate is largest among those near p: the cell of p holds every
  // face containing p; for a point outside all faces, rings of cells outwards up to the one after the first face.
  BarycentricPoint locate(const Vec2& p) const {
    BarycentricPoint best;
    double best_min = -std::numeric_limits<double>::infinity();
    const int cx = clamp_cell(p.x(), 0), cy = clamp_cell(p.y(), 1);
    // Outside every face: one more ring after the first face seen, for the nearest.
    int first_ring = -1;
    for (int r = 0; r <= g_ && best_min < 0 && (first_ring < 0 || r <= first_ring + 1); ++r) {
      if (first_ring < 0 && best.face >= 0) first_ring = r - 1;
      for (int y = std::max(0, cy - r); y <= std::min(g_ - 1, cy + r); ++y)
        for (int x = std::max(0, cx - r); x <= std::min(g_ - 1, cx + r); ++x) {
          if (std::max(std::abs(x - cx), std::abs(y - cy)) != r) continue;  // this ring only
          for (int f : cells_[y * g_ + x]) {
            double w[3];
            barycentric(p, corner(f, 0), corner(f, 1), corner(f, 2), w);
            const double m = std::min({w[0], w[1], w[2]});
            if (std::isfinite(m) && m > best_min) {
              best_min = m;
              best.face = f;
              std::copy(w, w + 3, best.w);
            }
          }
        }
    }
    if (best.face < 0) throw InputError("parameter map: no non-degenerate triangle to map into");
    double sum = 0;
    for (double& w : best.w) sum += (w = std::max(w, 0.0));
    for (double& w : best.w) w /= sum;
    return best;
  }

 private:
  const UV& uv_;
  const Faces& F_;
  int g_;
  Vec2 lo_;
  double cell_;
  std::vector<std::vector<int>> cells_;

  Vec2 corner(int f, int c) const { return uv_.row(F_(f, c)).transpose(); }
  int clamp_cell(double t, int axis) const {
    const double k = std::floor((t - lo_(axis)) / cell_);
    return static_cast<int>(std::clamp(k, 0.0, static_cast<double>(g_ - 1)));
  }
};

}  // namespace

std::vector<BarycentricPoint> locate_in_parameter_domain(const UV& uv, const Faces& F, const UV& query) {
  if (F.rows() == 0) throw InputError("parameter map: the patch has no faces");
  if (F.minCoeff() < 0 || F.maxCoeff() >= uv.rows())
    throw InputError("parameter map: a face indexes a vertex the parameterization does not have");
  const TriangleGrid grid(uv, F);
  std::vector<BarycentricPoint> out(static_cast<std::size_t>(query.rows()));
  for (Eigen::Index i = 0; i < query.rows(); ++i) out[i] = grid.locate(query.row(i).transpose());
  return out;
}

Points interpolate(const std::vector<BarycentricPoint>& at, const Faces& F, const Points& values) {
  Points out(static_cast<Eigen::Index>(at.size()), 3);
  for (std::size_t i = 0; i < at.size(); ++i) {
    out.row(static_cast<Eigen::Index>(i)).setZero();
    for (int c = 0; c < 3; ++c) out.row(static_cast<Eigen::Index>(i)) += at[i].w[c] * values.row(F(at[i].face, c));
  }
  return out;
}

}  // namespace db
