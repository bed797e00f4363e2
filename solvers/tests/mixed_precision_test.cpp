// multifrontal_mixed specifics (the registry's conformance suite covers it like every backend): a factor of half
// the bytes, refinement to the tolerance asked, a clear failure when the refinement cannot get there.
#include <random>
#include <string>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "solvers/base/error.h"
#include "solvers/linear_solver.h"
#include "solvers/tests/exact_reference.h"

namespace {

using db::DenseMat;
using db::SpMat;

//! The 3x3-block bi-Laplacian of an n-vertex path with both ends weighted: SPD, ill-conditioned as n grows
//! (condition ~ n^4), like the deformation systems.
SpMat path_system(int n) {
  std::vector<Eigen::Triplet<double>> t;
  SpMat L(n, n);
  for (int i = 0; i + 1 < n; ++i) {
    t.emplace_back(i, i, 1.0);
    t.emplace_back(i + 1, i + 1, 1.0);
    t.emplace_back(i, i + 1, -1.0);
    t.emplace_back(i + 1, i, -1.0);
  }
  L.setFromTriplets(t.begin(), t.end());
  SpMat A = SpMat(L.transpose()) * L;
  A.coeffRef(0, 0) += 1.0;
  A.coeffRef(n - 1, n - 1) += 1.0;
  t.clear();
  for (int j = 0; j < A.outerSize(); ++j)
    for (SpMat::InnerIterator it(A, j); it; ++it)
      for (int a = 0; a < 3; ++a) t.emplace_back(3 * int(it.row()) + a, 3 * j + a, it.value() * (1.0 + 0.5 * a));
  SpMat K(3 * n, 3 * n);
  K.setFromTriplets(t.begin(), t.end());
  SpMat U = K.triangularView<Eigen::Upper>();
  U.makeCompressed();
  return U;
}

DenseMat rhs(Eigen::Index n, int cols) {
  std::mt19937 rng(3);
  std::normal_distribution<double> g;
  DenseMat B(n, cols);
  for (Eigen::Index i = 0; i < B.size(); ++i) B.data()[i] = g(rng);
  return B;
}

db::SolverOptions options(double tolerance, int max_iterations) {
  db::SolverOptions o;
  o.block_size = 3;
  o.tolerance = tolerance;
  o.max_iterations = max_iterations;
  return o;
}

TEST(MultifrontalMixed, HalfTheFactorBytesAndTheDoubleAnswer) {
  const SpMat U = path_system(250);
  const DenseMat B = rhs(U.rows(), 3);
  auto dbl = db::make_solver("multifrontal", options(1e-10, 1000));
  auto mix = db::make_solver("multifrontal_mixed", options(1e-13, 1000));
  DenseMat Xd, Xm;
  for (auto* s : {dbl.get(), mix.get()}) {
    s->analyze(U);
    s->factorize(U);
  }
  dbl->solve(B, Xd);
  mix->solve(B, Xm);
  const db::FactorStats sd = dbl->stats(), sm = mix->stats();
  EXPECT_EQ(sm.nnz_factor, sd.nnz_factor);
  // The entries are half; the indices (the same for both) are not.
  EXPECT_EQ(sd.factor_bytes - sm.factor_bytes, sd.nnz_factor * 4) << "entries stored per FactorBlock trapezoid";
  EXPECT_GT(sm.iterations, 0);
  EXPECT_LE(sm.last_correction, 1e-13);
  // Xm's true residual (exact_reference.h): in double the product's own rounding is of the residual's size.
  const double residual = db::exact::exact_residual(U, Xm, B);
  EXPECT_NEAR(sm.achieved_tolerance, residual, 0.5 * residual + 1e-15);  // what it reports is the true residual
  // Against the exact solution (dense LL^T in long double): mixed is closer than a double direct solve may be, a
  // hundredth of the error its rounding allows on this system (the double solve's own error is not the yardstick:
  // it depends on the BLAS kernels and the thread count).
  const SpMat full = SpMat(U.selfadjointView<Eigen::Upper>());
  const Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic> Al = DenseMat(full).cast<long double>();
  const DenseMat Xe = Al.llt().solve(B.cast<long double>()).cast<double>();
  const double err_mixed = db::exact::rel(Xm, Xe), err_double = db::exact::rel(Xd, Xe);
  EXPECT_WITHIN(err_mixed, 1e-10) << "double: " << err_double << ", iterations " << sm.iterations;
  EXPECT_WITHIN(err_mixed, 1e-2 * db::exact::solve_bound(db::exact::condition_number(U))) << "double: " << err_double;
}

TEST(MultifrontalMixed, RefinementThatCannotConvergeIsAnError) {
  const SpMat U = path_system(300);
  const DenseMat B = rhs(U.rows(), 1);
  for (int cap : {0, 1}) {
    auto s = db::make_solver("multifrontal_mixed", options(1e-14, cap));
    s->analyze(U);
    s->factorize(U);
    DenseMat X;
    try {
      s->solve(B, X);
      FAIL() << "an unconverged refinement returned an answer (cap " << cap << ")";
    } catch (const db::SolverError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("relative correction of 1e-14"), std::string::npos) << what;
      EXPECT_NE(what.find("iteration cap"), std::string::npos) << what;
    }
  }
}

TEST(MultifrontalMixed, OutOfCoreStagingGivesTheSameFactor) {
  const SpMat U = path_system(500);
  const DenseMat B = rhs(U.rows(), 2);
  db::SolverOptions on_disk = options(1e-12, 1000);
  on_disk.factor_dir = testing::TempDir();
  auto mem = db::make_solver("multifrontal_mixed", options(1e-12, 1000));
  auto disk = db::make_solver("multifrontal_mixed", on_disk);
  DenseMat Xm, Xd;
  for (auto* s : {mem.get(), disk.get()}) {
    s->analyze(U);
    s->factorize(U);
  }
  mem->solve(B, Xm);
  disk->solve(B, Xd);
  EXPECT_FALSE(disk->stats().factor_on_disk);  // staged there, held in memory rounded
  EXPECT_EQ(disk->stats().factor_bytes, mem->stats().factor_bytes);
  EXPECT_EQ(disk->stats().iterations, mem->stats().iterations);
  // Both refined to the tolerance: each against the exact solution (exact_reference.h).
  const DenseMat Xe = db::exact::exact_solution(U, B, 3);
  EXPECT_WITHIN(db::exact::max_rel(Xm, Xe), db::exact::refined_bound(1e-12)) << "in memory";
  EXPECT_WITHIN(db::exact::max_rel(Xd, Xe), db::exact::refined_bound(1e-12)) << "staged";
}

}  // namespace
