#include "solvers/multifrontal/refinement.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "solvers/base/error.h"

namespace db::multifrontal {

void symmetric_product(const SpMat& upper, const RowMajorMat& X, RowMajorMat& Y) {
  const Index n = upper.cols(), r = X.cols();
  Y.setZero(n, r);
  const int* Ap = upper.outerIndexPtr();
  const int* Ai = upper.innerIndexPtr();
  const double* Ax = upper.valuePtr();
  const double* x = X.data();
  double* y = Y.data();
  for (Index j = 0; j < n; ++j) {
    const double* xj = x + j * r;
    double* yj = y + j * r;
    for (int p = Ap[j]; p < Ap[j + 1]; ++p) {
      const Index i = Ai[p];
      const double a = Ax[p];
      double* yi = y + i * r;
      const double* xi = x + i * r;
      for (Index c = 0; c < r; ++c) yi[c] += a * xj[c];
      if (i != j)
        for (Index c = 0; c < r; ++c) yj[c] += a * xi[c];
    }
  }
}

namespace {

//! hi + lo -= a x, exactly up to the rounding of lo: Dekker's product and Knuth's sum (error-free transformations;
//! the file is compiled with -ffp-contract=off so that no step is fused).
inline void subtract_product(double& hi, double& lo, double a, double x) {
  constexpr double kSplit = 134217729.0;  // 2^27 + 1
  const double p = a * x;
  const double ca = kSplit * a, ah = ca - (ca - a), al = a - ah;
  const double cx = kSplit * x, xh = cx - (cx - x), xl = x - xh;
  const double pe = ((ah * xh - p) + ah * xl + al * xh) + al * xl;  // a x = p + pe exactly
  const double s = hi - p, v = s - hi;
  const double se = (hi - (s - v)) - (p + v);  // hi - p = s + se exactly
  hi = s;
  lo += se - pe;
}

}  // namespace

void extended_residual_parts(const SpMat& upper, const RowMajorMat& X, const RowMajorMat& B, RowMajorMat& R,
                             std::vector<double>& low) {
  const Index n = upper.cols(), r = X.cols();
  R = B;  // the high parts
  low.assign(std::size_t(n * r), 0.0);
  const int* Ap = upper.outerIndexPtr();
  const int* Ai = upper.innerIndexPtr();
  const double* Ax = upper.valuePtr();
  const double* x = X.data();
  double* hi = R.data();
  for (Index j = 0; j < n; ++j)
    for (int p = Ap[j]; p < Ap[j + 1]; ++p) {
      const Index i = Ai[p];
      for (Index c = 0; c < r; ++c) {
        subtract_product(hi[i * r + c], low[std::size_t(i * r + c)], Ax[p], x[j * r + c]);
        if (i != j) subtract_product(hi[j * r + c], low[std::size_t(j * r + c)], Ax[p], x[i * r + c]);
      }
    }
}

void extended_residual(const SpMat& upper, const RowMajorMat& X, const RowMajorMat& B, RowMajorMat& R) {
  std::vector<double> low;
  extended_residual_parts(upper, X, B, R, low);
  double* hi = R.data();
  for (Index k = 0; k < R.size(); ++k) hi[k] += low[std::size_t(k)];
}

RefinedSystem refined_system(const SpMat& upper) {
  return {[&upper](const RowMajorMat& X, RowMajorMat& Y) { symmetric_product(upper, X, Y); },
          [&upper](const RowMajorMat& X, const RowMajorMat& B, RowMajorMat& R) { extended_residual(upper, X, B, R); }};
}

namespace {

//! Relative residual a correction's CG solve stops at (recursive): each refinement step then removes all but
//! about this fraction of x's error, and a few steps reach any tolerance down to the rounding of x.
constexpr double kInnerTolerance = 1e-6;

//! Conjugate gradients on A D = R for the active columns, D from 0, each until its recursive residual is
//! kInnerTolerance of its start; stops early when `budget` iterations are spent. Returns the iterations run.
struct CorrectionSolve {
  const RefinedSystem& A;
  const std::string& who;
  const std::function<void(RowMajorMat&)>& precondition;
  const std::vector<char>& active;
  RowMajorMat Z, P, Q;

  int run(RowMajorMat& R, RowMajorMat& D, int budget) {
    const Index cols = R.cols();
    D.setZero(R.rows(), cols);
    std::vector<double> rz(static_cast<std::size_t>(cols)), goal(static_cast<std::size_t>(cols));
    std::vector<char> going = active;
    for (Index c = 0; c < cols; ++c) going[std::size_t(c)] = going[std::size_t(c)] && R.col(c).norm() > 0;  // solved
    for (Index c = 0; c < cols; ++c) goal[std::size_t(c)] = kInnerTolerance * R.col(c).norm();
    Z = R;
    precondition(Z);
    P = Z;
    for (Index c = 0; c < cols; ++c) rz[std::size_t(c)] = R.col(c).dot(Z.col(c));
    int it = 0;
    while (it < budget && std::find(going.begin(), going.end(), 1) != going.end()) {
      ++it;
      A.product(P, Q);
      for (Index c = 0; c < cols; ++c) {
        if (!going[std::size_t(c)]) continue;
        const double pq = P.col(c).dot(Q.col(c));
        if (!(pq > 0))
          throw SolverError(fmt::format("{}: refinement met p^T A p = {:.3g}: the matrix is not positive definite",
                                        who, pq));
        const double alpha = rz[std::size_t(c)] / pq;
        D.col(c) += alpha * P.col(c);
        R.col(c) -= alpha * Q.col(c);
        going[std::size_t(c)] = R.col(c).norm() > goal[std::size_t(c)];
      }
      if (std::find(going.begin(), going.end(), 1) == going.end()) break;
      Z = R;
      precondition(Z);
      for (Index c = 0; c < cols; ++c) {
        if (!going[std::size_t(c)]) continue;
        const double rz_new = R.col(c).dot(Z.col(c));
        P.col(c) = Z.col(c) + (rz_new / rz[std::size_t(c)]) * P.col(c);
        rz[std::size_t(c)] = rz_new;
      }
    }
    return it;
  }
};

SolverError not_converged(const std::string& who, double tolerance, double reached, int iterations,
                          const std::string& why) {
  return SolverError(fmt::format("{}: the refinement did not reach a relative correction of {:.3g} ({}; {:.3g} "
                                 "after {} CG iterations)",
                                 who, tolerance, why, reached, iterations));
}

double relative_max(const RowMajorMat& D, const RowMajorMat& X, Index c) {
  const double d = D.col(c).lpNorm<Eigen::Infinity>(), x = X.col(c).lpNorm<Eigen::Infinity>();
  return d == 0 ? 0.0 : x > 0 ? d / x : std::numeric_limits<double>::infinity();
}

}  // namespace

Refinement refine(const RefinedSystem& A, const std::function<void(RowMajorMat&)>& precondition,
                  const RowMajorMat& B, RowMajorMat& X, double tolerance, int max_iterations, const std::string& who) {
  const Index cols = B.cols();
  X = B;
  precondition(X);  // the rounded factor's own solution: the start
  std::vector<char> active(std::size_t(cols), 1);
  std::vector<double> before(std::size_t(cols), std::numeric_limits<double>::infinity());
  CorrectionSolve cg{A, who, precondition, active, {}, {}, {}};
  RowMajorMat R, D;
  Refinement out;
  out.last_correction = std::numeric_limits<double>::infinity();  // no correction yet
  while (std::find(active.begin(), active.end(), 1) != active.end()) {
    if (out.iterations >= max_iterations)
      throw not_converged(who, tolerance, out.last_correction, out.iterations,
                          fmt::format("the iteration cap, {}", max_iterations));
    A.residual(X, B, R);
    out.iterations += cg.run(R, D, max_iterations - out.iterations);
    ++out.steps;
    X += D;
    out.last_correction = 0;
    for (Index c = 0; c < cols; ++c) {
      if (!active[std::size_t(c)]) continue;
      const double dx = relative_max(D, X, c);
      out.last_correction = std::max(out.last_correction, dx);
      active[std::size_t(c)] = dx > tolerance;
      // A correction not even half the one before: the steps no longer gain on the rounding.
      if (active[std::size_t(c)] && !(dx < 0.5 * before[std::size_t(c)]) && out.iterations < max_iterations)
        throw not_converged(who, tolerance, dx, out.iterations,
                            "stalled: a correction no longer halves the one before");
      before[std::size_t(c)] = dx;
    }
  }
  A.residual(X, B, R);
  for (Index c = 0; c < cols; ++c) {
    const double b = B.col(c).norm();
    out.residual = std::max(out.residual, b > 0 ? R.col(c).norm() / b : R.col(c).norm());
  }
  return out;
}

}  // namespace db::multifrontal
