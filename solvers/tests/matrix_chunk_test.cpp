// The multifrontal backend's matrix chunks (multifrontal/matrix_chunk.h) against the lower triangle computed
// whole, and the backend on systems large enough for several chunks per subtree against the exact solution.
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "solvers/linear_solver.h"
#include "solvers/multifrontal/matrix_chunk.h"
#include "solvers/multifrontal/symbolic.h"
#include "solvers/tests/exact_reference.h"
#include "solvers/tests/worker_threads.h"

namespace {

using db::DenseMat;
using db::SpMat;
using db::multifrontal::MatrixChunk;

//! A TF-like system: the bi-Laplacian (2-ring pattern) of an nx x ny torus with random weights and a few
//! constrained vertices, plus `shift` on the diagonal, kron a 3x3 SPD block (unknowns interleaved per vertex).
SpMat tf_like(int nx, int ny, std::mt19937& rng, double shift = 0) {
  std::uniform_real_distribution<double> weight(0.5, 2.0);
  const int n = nx * ny;
  std::vector<Eigen::Triplet<double>> t;
  auto id = [&](int i, int j) { return ((i + nx) % nx) + nx * ((j + ny) % ny); };
  auto edge = [&](int a, int b) {
    const double w = weight(rng);
    t.insert(t.end(), {{a, b, -w}, {b, a, -w}, {a, a, w}, {b, b, w}});
  };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      edge(id(i, j), id(i + 1, j));
      edge(id(i, j), id(i, j + 1));
      edge(id(i, j), id(i + 1, j + 1));
    }
  SpMat L(n, n);
  L.setFromTriplets(t.begin(), t.end());
  SpMat A = SpMat(L.transpose()) * L;
  for (int v : {0, n / 3, n / 2}) A.coeffRef(v, v) += 4.0;
  for (int v = 0; v < n; ++v) A.coeffRef(v, v) += shift;
  Eigen::Matrix3d S;
  S << 2.0, 0.3, -0.2, 0.3, 1.5, 0.1, -0.2, 0.1, 1.0;
  t.clear();
  for (int j = 0; j < A.outerSize(); ++j)
    for (SpMat::InnerIterator it(A, j); it; ++it)
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) t.emplace_back(3 * int(it.row()) + a, 3 * j + b, it.value() * S(a, b));
  SpMat K(3 * n, 3 * n);
  K.setFromTriplets(t.begin(), t.end());
  return K;
}

//! Column j of the chunk equals column j of the whole lower triangle, rows and values.
void expect_columns(const MatrixChunk& M, const SpMat& lower, int c0, int c1) {
  for (int j = c0; j < c1; ++j) {
    ASSERT_EQ(M.count(j), lower.outerIndexPtr()[j + 1] - lower.outerIndexPtr()[j]) << "column " << j;
    for (int t = 0; t < M.count(j); ++t) {
      const int p = lower.outerIndexPtr()[j] + t;
      ASSERT_EQ(M.rows(j)[t], lower.innerIndexPtr()[p]) << "column " << j;
      ASSERT_EQ(M.values(j)[t], lower.valuePtr()[p]) << "column " << j;
    }
  }
}

TEST(MatrixChunk, RunsHoldTheLowerTriangle) {
  std::mt19937 rng(7);
  // The analysis' natural order keeps the matrix as given; its supernodes are those of the factorization.
  // 3600 unknowns: runs of several supernodes, and more than one run.
  const SpMat upper = tf_like(40, 30, rng).triangularView<Eigen::Upper>();
  const db::multifrontal::Symbolic S = db::multifrontal::analyze_blocks(upper, 3, "natural");
  const SpMat lower = upper.transpose();
  const std::vector<int> counts = MatrixChunk::lower_counts(upper);
  MatrixChunk M;
  int runs = 0, longest = 0;
  for (int s = 0; s < S.nsuper();) {
    const int e = MatrixChunk::run_end(S, s, S.nsuper() - 1);
    ASSERT_GE(e, s);
    M.load(upper, counts, S, s, e);
    expect_columns(M, lower, S.col0[std::size_t(s)], S.col0[std::size_t(e) + 1]);
    longest = std::max(longest, e - s + 1);
    ++runs;
    s = e + 1;
  }
  EXPECT_GT(runs, 1);
  EXPECT_GT(longest, 1);
  for (int s : {0, S.nsuper() / 2, S.nsuper() - 1}) {  // single supernodes, as the top phase loads them
    M.load(upper, counts, S, s, s);
    expect_columns(M, lower, S.col0[std::size_t(s)], S.col0[std::size_t(s) + 1]);
  }
}

TEST(MatrixChunk, LowerCountsAreTheRowCountsOnAnyThreads) {
  std::mt19937 rng(9);
  // 24000 unknowns in the natural order of a torus: many rows lie before their column's range (the wrap-around).
  const SpMat upper = tf_like(100, 80, rng).triangularView<Eigen::Upper>();
  std::vector<int> rows(std::size_t(upper.cols()), 0);
  for (int j = 0; j < upper.outerSize(); ++j)
    for (SpMat::InnerIterator it(upper, j); it; ++it) ++rows[std::size_t(it.row())];
  for (int threads : {1, 3, 4}) {
    db::test::WorkerThreads env(threads);
    EXPECT_EQ(MatrixChunk::lower_counts(upper), rows) << threads << " threads";
  }
}

TEST(MatrixChunk, MultifrontalIsExactOnSeveralRuns) {
  std::mt19937 rng(11);
  const SpMat full = tf_like(36, 30, rng, 0.1);  // 3240 unknowns; shifted: well conditioned
  const SpMat upper = full.triangularView<Eigen::Upper>();
  DenseMat B = DenseMat::Random(full.rows(), 3);
  // Against the exact solution under the system's bound (exact_reference.h), not another double solve.
  const DenseMat Xref = db::exact::exact_solution(upper, B, 3);
  const double tol = db::exact::solve_bound(db::exact::condition_number(upper));
  for (const char* ordering : {"natural", "metis"})
    for (int threads : {1, 2}) {
      SCOPED_TRACE(std::string(ordering) + " threads " + std::to_string(threads));
      const db::test::WorkerThreads scope(threads);
      db::SolverOptions o;
      o.ordering = ordering;
      o.block_size = 3;
      auto solver = db::make_solver("multifrontal", o);
      solver->factorize(upper);
      DenseMat X;
      solver->solve(B, X);
      EXPECT_WITHIN(db::exact::rel(X, Xref), tol);
    }
}

}  // namespace
