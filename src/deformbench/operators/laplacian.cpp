#include "operators/laplacian.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "solvers/base/resources.h"

namespace db {

const EnumText<Weights>& enum_text(Weights) {
  static const EnumText<Weights> t{"Laplacian weights", {{Weights::Uniform, "uniform"}, {Weights::Cotan, "cotan"}}};
  return t;
}

namespace {
//! f(i) for every vertex i < n, in vertex ranges on the worker threads: each vertex's entries depend on it alone,
//! so the bytes do not depend on the threads (serial init time on many cores otherwise).
template <class F>
void for_vertex_ranges(int n, F&& f) {
  run_ranges(n, 4096, [&](int lo, int hi) {
    for (int i = lo; i < hi; ++i) f(i);
  });
}

int slot(const Adjacency& adj, int i, int j) {
  const int* p = std::lower_bound(adj.begin(i), adj.end(i), j);
  return static_cast<int>(p - adj.nbr.data());
}
}  // namespace

std::vector<double> laplacian_weights(const Points& V, const Faces& F, const Adjacency& adj, Weights wt) {
  const int n = adj.num_vertices();
  std::vector<double> w(adj.nbr.size(), 0.0);
  if (wt == Weights::Uniform) {
    for_vertex_ranges(n, [&](int i) {
      for (int s = adj.off[i]; s < adj.off[i + 1]; ++s) w[s] = 1.0 / adj.degree(i);
    });
    return w;
  }
  // Cotangent weights: each triangle adds cot(angle at the opposite corner)/2 to its three edges.
  for (int f = 0; f < F.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int a = F(f, c), b = F(f, (c + 1) % 3), o = F(f, (c + 2) % 3);
      const Vec3 u = V.row(a) - V.row(o), v = V.row(b) - V.row(o);
      const double cot = u.dot(v) / std::max(u.cross(v).norm(), 1e-300);
      w[slot(adj, a, b)] += 0.5 * cot;
      w[slot(adj, b, a)] += 0.5 * cot;
    }
  }
  for (int i = 0; i < n; ++i) {
    double sum = 0;
    for (int s = adj.off[i]; s < adj.off[i + 1]; ++s) sum += w[s];
    if (!(std::abs(sum) > 1e-12) || !std::isfinite(sum))
      throw InputError(fmt::format("cotangent weights of vertex {} sum to {} (degenerate 1-ring); use uniform weights", i, sum));
    for (int s = adj.off[i]; s < adj.off[i + 1]; ++s) w[s] /= sum;
  }
  return w;
}

Points laplacian_coordinates(const Points& V, const Adjacency& adj, const std::vector<double>& w) {
  Points d(V.rows(), 3);
  for_vertex_ranges(adj.num_vertices(), [&](int i) {
    Eigen::RowVector3d acc = V.row(i);
    for (int s = adj.off[i]; s < adj.off[i + 1]; ++s) acc -= w[s] * V.row(adj.nbr[s]);
    d.row(i) = acc;
  });
  return d;
}

}  // namespace db
