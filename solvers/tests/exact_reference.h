#pragma once
//! What the tests measure a solve's accuracy against: the exact solution, and a tolerance derived from the
//! system's measured conditioning. Never another double solve under a fixed epsilon: a double solve's own error
//! (up to about eps cond(A)) depends on the BLAS kernels OpenBLAS picks, the CPU and the thread count, so two of
//! them agree to a fixed epsilon on one machine and not on the next.
//!  - exact_solution(): a long-double dense Cholesky for small systems, else multifrontal_refined (double factor,
//!    refinement with double-double residuals) refined until its last correction is kExactTolerance of x; either
//!    is exact to far below a double solve's error.
//!  - condition_number(): cond_2(A) of a symmetric positive definite A, from its extreme eigenvalues (dense
//!    eigenvalues when small, else power iteration for the largest and inverse iteration for the smallest).
//!  - exact_residual(): ||B - A X||_F / ||B||_F of a computed X, summed in quadruple precision: in double the
//!    product's own rounding is of the size of an accurate solution's residual.
//!  - pivot_ratio_error(): how far a computed pivot ratio may lie from the exact one.
//!  - solve_bound(): the relative forward error a backward-stable double solve may have, kSolveFactor eps cond.
//!  - refined_bound(): how far a refined solve (multifrontal_mixed, _refined, mumps_refined) may lie from the exact
//!    solution, in max_rel(): its refinement stops once the last correction is at most its tolerance relative to x
//!    (max-norms), after corrections that at least halved each time, so what is left is below the tolerance; twice
//!    the tolerance plus the exact solution's own.
//!  - EXPECT_WITHIN(err, bound): err < bound, and with DEFORMBENCH_TEST_MARGINS set in the environment every such
//!    check prints err, bound and their ratio (the margins a report quotes).
//! Header only: the solver tests link the solver library alone, the mesh-level tests include it too.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <random>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "solvers/linear_solver.h"

namespace db::exact {

constexpr double kEps = std::numeric_limits<double>::epsilon();
//! multifrontal_refined's tolerance for the exact solution: the last correction's size relative to x (max-norms).
constexpr double kExactTolerance = 1e-13;
//! The multiple of eps cond(A) a backward-stable solve's relative forward error stays under. The worst-case
//! bound grows with n (Higham, Accuracy and Stability, thm. 10.4); in practice the error is a small multiple of
//! eps cond(A), and cond(A) below is estimated from under (power and inverse iterations), so some room stays.
constexpr double kSolveFactor = 16;
//! Systems up to this order get the long-double dense reference and dense eigenvalues.
constexpr Eigen::Index kDenseLimit = 700;

//! The whole symmetric matrix from its upper triangle.
inline SpMat full_of(const SpMat& upper) { return SpMat(upper.selfadjointView<Eigen::Upper>()); }

//! A X = B solved exactly (to far below a double solve's error), A given by its upper triangle.
inline DenseMat exact_solution(const SpMat& upper, const DenseMat& B, int block_size = 1) {
  if (upper.rows() <= kDenseLimit) {
    using LongMat = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
    const LongMat A = DenseMat(full_of(upper)).cast<long double>();
    return A.llt().solve(B.cast<long double>()).cast<double>();
  }
  SolverOptions o;
  o.block_size = block_size;
  o.tolerance = kExactTolerance;
  auto s = make_solver("multifrontal_refined", o);
  s->factorize(upper);
  DenseMat X;
  s->solve(B, X);
  return X;
}

//! ||B - A X||_F / ||B||_F, A given by its upper triangle, every product and sum in __float128.
inline double exact_residual(const SpMat& upper, const DenseMat& X, const DenseMat& B) {
  using Quad = __float128;
  Quad r2 = 0, b2 = 0;
  for (Eigen::Index c = 0; c < B.cols(); ++c) {
    std::vector<Quad> r(std::size_t(B.rows()));
    for (Eigen::Index i = 0; i < B.rows(); ++i) r[std::size_t(i)] = B(i, c);
    for (Eigen::Index j = 0; j < upper.outerSize(); ++j)
      for (SpMat::InnerIterator it(upper, j); it; ++it) {
        const Eigen::Index i = it.row();
        r[std::size_t(i)] -= Quad(it.value()) * Quad(X(j, c));
        if (i != j) r[std::size_t(j)] -= Quad(it.value()) * Quad(X(i, c));
      }
    for (Eigen::Index i = 0; i < B.rows(); ++i) {
      r2 += r[std::size_t(i)] * r[std::size_t(i)];
      b2 += Quad(B(i, c)) * Quad(B(i, c));
    }
  }
  return std::sqrt(double(r2 / b2));
}

//! cond_2(A) of a symmetric positive definite A (upper triangle). Large systems: both extreme eigenvalues are
//! approached from inside the spectrum, so the estimate is at most the true value (a tolerance from it is tight).
inline double condition_number(const SpMat& upper) {
  const SpMat A = full_of(upper);
  if (A.rows() <= kDenseLimit) {
    const Eigen::SelfAdjointEigenSolver<DenseMat> eig(DenseMat(A), Eigen::EigenvaluesOnly);
    const Eigen::VectorXd& ev = eig.eigenvalues();
    return ev(ev.size() - 1) / ev(0);
  }
  std::mt19937 rng(1);
  std::normal_distribution<double> g;
  DenseMat v(A.rows(), 1);
  for (Eigen::Index i = 0; i < v.rows(); ++i) v(i, 0) = g(rng);
  const DenseMat start = v.normalized();
  auto rayleigh = [&](const DenseMat& x) { return (x.transpose() * (A * x))(0, 0) / x.squaredNorm(); };
  v = start;
  for (int k = 0; k < 100; ++k) v = (A * v).normalized();
  const double lmax = rayleigh(v);
  SolverOptions o;
  auto s = make_solver("cholmod_supernodal", o);
  s->factorize(upper);
  v = start;
  for (int k = 0; k < 30; ++k) {
    DenseMat w;
    s->solve(v, w);
    v = w.normalized();
  }
  return lmax / rayleigh(v);
}

//! The relative forward error a backward-stable double solve of a system of condition `cond` may have.
inline double solve_bound(double cond) { return kSolveFactor * kEps * cond; }

//! How far a computed pivot ratio d_k / A_kk (FactorStats::min_pivot_ratio) of an n x n matrix may lie from the
//! exact one: d_k = A_kk - sum_j L_kj^2 (the sum of k terms whose total is at most A_kk) rounds by at most about
//! k eps A_kk (Higham, Accuracy and Stability, thm. 10.3), with a factor 4 of room for the rounding of L_kj.
inline double pivot_ratio_error(std::size_t n) { return 4 * double(n) * kEps; }

//! How far a refined solve at `tolerance` may lie from exact_solution(), in max_rel().
inline double refined_bound(double tolerance) { return 2 * (tolerance + kExactTolerance); }

//! ||a - b||_F / ||b||_F.
template <class A, class B>
double rel(const A& a, const B& b) {
  return (a - b).norm() / b.norm();
}
//! ||a - b||_max / ||b||_max (the refinements' measure).
template <class A, class B>
double max_rel(const A& a, const B& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

//! The predicate of EXPECT_WITHIN.
inline ::testing::AssertionResult within(const char* err_text, const char* bound_text, double err, double bound) {
  if (std::getenv("DEFORMBENCH_TEST_MARGINS")) {
    const ::testing::TestInfo* t = ::testing::UnitTest::GetInstance()->current_test_info();
    std::printf("[margin] %s.%s: %s = %.3g, %s = %.3g, ratio %.3g\n", t->test_suite_name(), t->name(), err_text, err,
                bound_text, bound, err / bound);
  }
  if (err < bound) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << err_text << " = " << err << " is not below " << bound_text << " = " << bound;
}

}  // namespace db::exact

#define EXPECT_WITHIN(err, bound) EXPECT_PRED_FORMAT2(::db::exact::within, err, bound)
