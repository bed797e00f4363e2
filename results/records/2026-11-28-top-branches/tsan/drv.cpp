// TSan driver (not part of the project): the multifrontal backend at several thread counts on a 3x3-block grid.
#include <cstdio>
#include <cstdlib>
#include <vector>
#include <Eigen/Sparse>
#include "solvers/linear_solver.h"
db::SpMat grid_upper(int g, int h) {
  std::vector<Eigen::Triplet<double>> t;
  for (int x = 0; x < g; ++x)
    for (int y = 0; y < h; ++y) {
      const int v = x * h + y;
      t.emplace_back(v, v, 5.0);
      if (x + 1 < g) t.emplace_back(v, v + h, -1.0);
      if (y + 1 < h) t.emplace_back(v, v + 1, -1.0);
    }
  db::SpMat U(g * h, g * h);
  U.setFromTriplets(t.begin(), t.end());
  return U;
}
db::SpMat blocks_of(const db::SpMat& U, int b) {
  std::vector<Eigen::Triplet<double>> t;
  for (int j = 0; j < U.outerSize(); ++j)
    for (db::SpMat::InnerIterator it(U, j); it; ++it)
      for (int c = 0; c < b; ++c)
        for (int r = 0; r < b; ++r)
          if (it.row() < j || r <= c) t.emplace_back(b * int(it.row()) + r, b * j + c, it.row() < j ? (r == c ? -1.0 : -0.01) : (r == c ? 5.0 : 0.1));
  db::SpMat B(b * U.rows(), b * U.cols());
  B.setFromTriplets(t.begin(), t.end());
  return B;
}
int main() {
  const db::SpMat U = blocks_of(grid_upper(90, 90), 3);
  db::DenseMat B = db::DenseMat::Ones(U.rows(), 1), X[3];
  const char* T[3] = {"2", "8", "16"};
  for (int k = 0; k < 3; ++k) {
    setenv("DEFORMBENCH_THREADS", T[k], 1);
    db::SolverOptions o;
    o.block_size = 3;
    o.ordering = "metis";
    auto s = db::make_solver("multifrontal", o);
    s->analyze(U);
    s->factorize(U);
    s->solve(B, X[k]);
    const auto st = s->stats();
    std::printf("threads %s top flops %.3g of %.3g, top s %.4f, x0 %.17g\n", T[k], st.top_flops, st.flops, st.top_seconds, X[k](0, 0));
  }
  return 0;
}
