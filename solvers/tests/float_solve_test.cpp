// The mixed backend's solve with its float factor (float_factor.h): the double solve's supernodes, threads and
// kernels reading float entries. Checked on a synthetic factor (well conditioned, so the comparison resolves
// rounding) laid out on a real supernodal structure split among threads: against the exact solve with the rounded
// entries (dense, in long double), and against the double solve on the same rounded entries, which it reproduces.
#include <algorithm>
#include <cstdio>
#include <random>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "solvers/multifrontal/float_factor.h"
#include "solvers/multifrontal/schedule.h"
#include "solvers/multifrontal/storage.h"
#include "solvers/multifrontal/symbolic.h"
#include "solvers/multifrontal/triangular_solve.h"

namespace {

using namespace db::multifrontal;
using db::DenseMat;
using db::SpMat;

//! Upper triangle of a g x g grid's graph Laplacian plus the identity, in 3x3 blocks: nested dissection gives
//! a bushy assembly tree with subtrees for several threads.
SpMat grid_system(int g) {
  std::vector<Eigen::Triplet<double>> t;
  auto id = [g](int x, int y) { return x * g + y; };
  for (int x = 0; x < g; ++x)
    for (int y = 0; y < g; ++y) {
      const int v = id(x, y);
      for (int a = 0; a < 3; ++a) t.emplace_back(3 * v + a, 3 * v + a, 5.0);
      for (int w : {x + 1 < g ? id(x + 1, y) : -1, y + 1 < g ? id(x, y + 1) : -1})
        if (w >= 0)
          for (int a = 0; a < 3; ++a) t.emplace_back(3 * v + a, 3 * w + a, -1.0);
    }
  SpMat U(3 * g * g, 3 * g * g);
  U.setFromTriplets(t.begin(), t.end());
  U.makeCompressed();
  return U;
}

//! Entry (row i, column k) of a FactorBlock, both local to the supernode (i >= k).
double& entry(const FactorBlock& L, int i, int k) {
  const int p = k / FactorBlock::kWidth, c0 = L.c0(p), w = L.width(p), j = k - c0;
  if (i < c0 + w) return L.tri(p)[packed_column(j, w) + std::size_t(i - k)];
  return L.rect(p)[std::size_t(j) * std::size_t(L.height(p)) + std::size_t(i - c0 - w)];
}

struct Case {
  Symbolic S;
  Mapping values;   //!< a synthetic factor, entries already representable in float
  Eigen::MatrixXd dense;  //!< the same L, dense
};

//! `dense`: also the dense L (for small grids only).
Case make_case(int g, bool dense = true) {
  Case c{analyze_blocks(grid_system(g), 3, "metis"), {}, {}};
  const Symbolic& S = c.S;
  c.values = Mapping(S.xptr.back(), "the test factor");
  if (dense) c.dense = Eigen::MatrixXd::Zero(S.n, S.n);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  const FactorView F{S, c.values};
  for (int s = 0; s < S.nsuper(); ++s) {
    const FactorBlock L = F.block(s);
    const int* R = S.rows.data() + S.rptr[std::size_t(s)];
    for (int k = 0; k < L.n; ++k)
      for (int i = k; i < L.m; ++i) {
        // Diagonally dominant columns: L is well conditioned, the solves' rounding stays near double's.
        const double v = float(i == k ? 2.0 + 0.5 * u(rng) : 0.3 * u(rng) / std::sqrt(double(L.m)));
        entry(L, i, k) = v;
        if (dense) c.dense(R[i], R[k]) = v;
      }
  }
  return c;
}

DenseMat rhs(int n, int cols) {
  std::mt19937 rng(11);
  std::normal_distribution<double> gauss;
  DenseMat B(n, cols);
  for (Eigen::Index i = 0; i < B.size(); ++i) B.data()[i] = gauss(rng);
  return B;
}

TEST(FloatFactorSolve, ThreadedSolveMatchesTheDenseSolveAndTheDoubleKernels) {
  const Case c = make_case(14);  // 588 unknowns
  const Symbolic& S = c.S;
  const FloatFactor F32(FactorView{S, c.values});
  ASSERT_EQ(F32.bytes(), S.xptr.back() * sizeof(float));
  std::vector<double> cost(std::size_t(S.nsuper()));
  for (int s = 0; s < S.nsuper(); ++s) cost[std::size_t(s)] = double(S.xptr[std::size_t(s) + 1] - S.xptr[std::size_t(s)]);
  for (int threads : {1, 3}) {
    const Plan plan = schedule(S, threads, cost);
    if (threads > 1) {
      EXPECT_GT(plan.subtrees.size(), 1u) << "the test should exercise the threaded phase";
    }
    for (int cols : {1, 3, 5}) {  // the general kernels, the row kernel (2-4), three + two at a time
      const DenseMat B = rhs(S.n, cols);
      using LongMat = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;  // exact: no double rounding
      const LongMat L = c.dense.cast<long double>();
      const LongMat Y = L.triangularView<Eigen::Lower>().solve(B.cast<long double>());
      const DenseMat want = L.transpose().triangularView<Eigen::Upper>().solve(Y).cast<double>();
      RowMajorMat y32 = B, y64 = B;
      std::vector<RowMajorMat> acc;
      F32.solve(S, plan, y32, acc);
      forward_all(FactorView{S, c.values}, plan, y64, acc);
      backward_all(FactorView{S, c.values}, plan, y64);
      EXPECT_LT((DenseMat(y32) - want).norm() / want.norm(), 1e-14) << threads << " threads, " << cols << " columns";
      // Widening a float is exact: the float kernels compute what the double ones do on the rounded entries, up
      // to how the compiler vectorizes and fuses each (bitwise the same with the row kernel, three columns).
      const double apart = (DenseMat(y32) - DenseMat(y64)).norm() / want.norm();
      EXPECT_LT(apart, 1e-15) << threads << " threads, " << cols << " columns";
      if (cols == 3) {
        EXPECT_EQ(apart, 0.0);
      }
      std::printf("%d threads, %d columns: %.3g from dense, %.3g from the double kernels\n", threads, cols,
                  (DenseMat(y32) - want).norm() / want.norm(), apart);
    }
  }
}

// The top supernodes shared by a team (Plan::top_team, triangular_solve.h): the same bytes as the serial top, in
// both directions, for the double and the float factor, with the general kernels (1, 5 columns) and the row
// kernel (3). A grid whose top fronts (of an 8-thread plan) have more rows than a forward tile and more columns
// than a backward one.
TEST(TopTeamSolve, SameBytesAsTheSerialTop) {
  const Case c = make_case(120, false);
  const Symbolic& S = c.S;
  const FloatFactor F32(FactorView{S, c.values});
  std::vector<double> cost(std::size_t(S.nsuper()));
  for (int s = 0; s < S.nsuper(); ++s) cost[std::size_t(s)] = double(S.xptr[std::size_t(s) + 1] - S.xptr[std::size_t(s)]);
  Plan plan = schedule(S, 8, cost);
  int tall = 0, wide = 0;  // top supernodes with a panel rectangle over one forward tile, over one backward tile
  for (int s : plan.top) {
    tall += S.nrows(s) - std::min(S.ncols(s), FactorBlock::kWidth) > 256;
    wide += S.ncols(s) > 32 && S.nrows(s) > S.ncols(s);
  }
  ASSERT_GT(tall, 0);
  ASSERT_GT(wide, 0);
  for (int cols : {1, 3, 5}) {
    const DenseMat B = rhs(S.n, cols);
    RowMajorMat y[2][2];  // [team of 1 or 3][double or float factor]
    std::vector<RowMajorMat> acc;
    for (int k = 0; k < 2; ++k) {
      plan.top_team = k == 0 ? 1 : 3;
      y[k][0] = y[k][1] = B;
      forward_all(FactorView{S, c.values}, plan, y[k][0], acc);
      backward_all(FactorView{S, c.values}, plan, y[k][0]);
      F32.solve(S, plan, y[k][1], acc);
    }
    EXPECT_TRUE(y[1][0] == y[0][0]) << cols << " columns, double factor";
    EXPECT_TRUE(y[1][1] == y[0][1]) << cols << " columns, float factor";
    EXPECT_TRUE(y[0][0].allFinite());
  }
}

}  // namespace
