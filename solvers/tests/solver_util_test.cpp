// The backends' shared prologue (solvers/solver_util.h) on matrices large enough for several column ranges: the
// same verdicts and values on one thread as on several, against what the matrix holds.
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "solvers/base/error.h"
#include "solvers/solver_util.h"
#include "solvers/tests/worker_threads.h"

namespace {

using db::DenseVec;
using db::SpMat;

//! The upper triangle of a random banded SPD-like pattern: 20000 columns (several ranges of 4096 on 4 threads),
//! each with its diagonal and up to six entries above it.
SpMat banded_upper(std::mt19937& rng) {
  const int n = 20000;
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::vector<Eigen::Triplet<double>> t;
  for (int j = 0; j < n; ++j) {
    t.emplace_back(j, j, 10.0 + value(rng));
    for (int d : {1, 3, 7, 40, 900, 5000})
      if (j - d >= 0 && value(rng) > -0.2) t.emplace_back(j - d, j, value(rng));
  }
  SpMat A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

TEST(SolverUtil, DiagonalIsTheStoredDiagonalOnAnyThreads) {
  std::mt19937 rng(3);
  const SpMat A = banded_upper(rng);
  for (int threads : {1, 4}) {
    db::test::WorkerThreads env(threads);
    const DenseVec d = db::solver_util::diagonal_of(A);
    ASSERT_EQ(d.size(), A.cols());
    for (int j = 0; j < A.cols(); ++j) ASSERT_EQ(d(j), A.coeff(j, j)) << "column " << j;
  }
}

TEST(SolverUtil, NonFiniteEntryNamedByItsFirstColumnOnAnyThreads) {
  std::mt19937 rng(4);
  SpMat A = banded_upper(rng);
  db::solver_util::check_finite_values(A, "test");  // all finite: no throw
  // Non-finite entries in two ranges' columns: the earlier column is named whatever range a thread ends first.
  A.coeffRef(17000, 17000) = std::nan("");
  A.coeffRef(4100, 9100) = INFINITY;
  A.coeffRef(12000, 12000) = -INFINITY;
  for (int threads : {1, 2, 4}) {
    db::test::WorkerThreads env(threads);
    try {
      db::solver_util::check_finite_values(A, "test");
      FAIL() << "no throw at " << threads << " threads";
    } catch (const db::SolverError& e) {
      EXPECT_EQ(std::string(e.what()), "test: non-finite matrix entry inf at (4100, 9100)") << threads << " threads";
    }
  }
}

TEST(SolverUtil, PatternGuardAcrossThreadCounts) {
  std::mt19937 rng(5);
  const SpMat A = banded_upper(rng);
  db::solver_util::PatternGuard guard;
  {
    db::test::WorkerThreads env(4);
    guard.remember(A);
  }
  db::test::WorkerThreads env(1);
  EXPECT_NO_THROW(guard.check(A, "test"));  // the same pattern, hashed on another thread count
  SpMat moved = A;
  moved.innerIndexPtr()[moved.outerIndexPtr()[15000]] -= 1;  // one row index changed, same size and count
  EXPECT_THROW(guard.check(moved, "test"), db::SolverError);
}

}  // namespace
