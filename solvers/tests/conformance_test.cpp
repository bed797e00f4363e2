// Conformance of every registered solver backend (TEST_P over solver_names()), plus backend specifics.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <utility>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "solvers/base/error.h"
#include "solvers/base/resources.h"
#include "solvers/least_squares.h"
#include "solvers/linear_solver.h"
#include "solvers/tests/exact_reference.h"
#include "solvers/tests/worker_threads.h"

namespace {

using db::DenseMat;
using db::SpMat;
using Triplets = std::vector<Eigen::Triplet<double>>;

//! Weighted graph Laplacian of an nx x ny grid triangulated with one diagonal per quad
//! (6 neighbours inside, like a regular triangle mesh); `torus` wraps both directions.
SpMat mesh_laplacian(int nx, int ny, bool torus, std::mt19937& rng) {
  std::uniform_real_distribution<double> weight(0.5, 2.0);
  const int n = nx * ny;
  Triplets t;
  auto id = [&](int i, int j) { return ((i + nx) % nx) + nx * ((j + ny) % ny); };
  auto edge = [&](int a, int b) {
    const double w = weight(rng);
    t.emplace_back(a, b, -w);
    t.emplace_back(b, a, -w);
    t.emplace_back(a, a, w);
    t.emplace_back(b, b, w);
  };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const bool right = torus || i + 1 < nx, up = torus || j + 1 < ny;
      if (right) edge(id(i, j), id(i + 1, j));
      if (up) edge(id(i, j), id(i, j + 1));
      if (right && up) edge(id(i, j), id(i + 1, j + 1));
    }
  SpMat L(n, n);
  L.setFromTriplets(t.begin(), t.end());
  return L;
}

//! L^T L + diag(w^2) on a few constrained vertices: the bi-Laplacian normal equations (2-ring pattern).
SpMat normal_equations(const SpMat& L, int constrained, std::mt19937& rng) {
  SpMat A = SpMat(L.transpose()) * L;
  std::uniform_int_distribution<int> vertex(0, int(L.rows()) - 1);
  for (int k = 0; k < constrained; ++k) {
    const int v = vertex(rng);
    A.coeffRef(v, v) += 4.0;  // w = 2
  }
  A.makeCompressed();
  return A;
}

//! kron(A, S) with a 3x3 SPD S: unknowns interleaved x,y,z per vertex, as in transform-fitted systems.
SpMat kron3(const SpMat& A) {
  Eigen::Matrix3d S;
  S << 2.0, 0.3, -0.2, 0.3, 1.5, 0.1, -0.2, 0.1, 1.0;
  Triplets t;
  for (int j = 0; j < A.outerSize(); ++j)
    for (SpMat::InnerIterator it(A, j); it; ++it)
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) t.emplace_back(3 * it.row() + a, 3 * j + b, it.value() * S(a, b));
  SpMat K(3 * A.rows(), 3 * A.cols());
  K.setFromTriplets(t.begin(), t.end());
  return K;
}

SpMat upper_of(const SpMat& full) {
  SpMat U = full.triangularView<Eigen::Upper>();
  U.makeCompressed();
  return U;
}

DenseMat random_rhs(Eigen::Index n, int k, std::mt19937& rng) {
  std::normal_distribution<double> g;
  DenseMat B(n, k);
  for (Eigen::Index i = 0; i < B.size(); ++i) B.data()[i] = g(rng);
  return B;
}

struct Problem {
  std::string label;
  SpMat full;
  int block_size;
};

std::vector<Problem> problems() {
  std::mt19937 rng(12345);
  std::vector<Problem> p;
  p.push_back({"torus9x8", normal_equations(mesh_laplacian(9, 8, true, rng), 3, rng), 1});
  p.push_back({"grid12x7", normal_equations(mesh_laplacian(12, 7, false, rng), 2, rng), 1});
  p.push_back({"torus6x5_block3", kron3(normal_equations(mesh_laplacian(6, 5, true, rng), 4, rng)), 3});
  return p;
}

using db::exact::pivot_ratio_error;
using db::exact::rel;

class Conformance : public ::testing::TestWithParam<std::string> {
 protected:
  db::SolverInfo info() const { return db::solver_info(GetParam()); }
  static constexpr double kTolerance = 1e-12;
  db::SolverOptions options(const std::string& ordering, int block) const {
    db::SolverOptions o;
    o.ordering = ordering;
    o.block_size = block;
    o.tolerance = kTolerance;
    return o;
  }
  bool iterative() const { return info().family == "iterative"; }
  //! The relative forward error this backend may have on a system of condition `cond`: a direct solve's is a
  //! backward-stable one's (exact::solve_bound; the refining backends' is far below), an iterative one's at most
  //! its relative residual, kTolerance, times cond (with exact::kSolveFactor's room, as for the direct ones).
  double bound(double cond) const {
    return iterative() ? db::exact::kSolveFactor * cond * kTolerance : db::exact::solve_bound(cond);
  }
};

// Against the exact solution (exact_reference.h) under the bound the system's conditioning allows the backend.
TEST_P(Conformance, SolvesMeshSystems) {
  const db::SolverInfo si = info();
  const double tol = iterative() ? 1e-6 : 1e-8;  // residuals relative to B
  std::mt19937 rng(7);
  for (const Problem& pr : problems()) {
    const SpMat upper = upper_of(pr.full);
    const DenseMat dense = DenseMat(pr.full);
    const double forward = bound(db::exact::condition_number(upper));  // cond does not change with the scale
    for (const std::string& ordering : si.orderings)
      for (int block : {1, pr.block_size}) {
        SCOPED_TRACE(fmt::format("{} ordering={} block={}", pr.label, ordering, block));
        auto solver = db::make_solver(GetParam(), options(ordering, block));
        EXPECT_EQ(solver->name(), GetParam());
        solver->analyze(upper);
        // Two numeric factorizations on one analysis: the per-edit workflow.
        for (double scale : {1.0, 2.5}) {
          SpMat U = upper * scale;
          const DenseMat B = random_rhs(U.rows(), 3, rng);
          solver->factorize(U);
          DenseMat X;
          solver->solve(B, X);
          ASSERT_EQ(X.rows(), B.rows());
          ASSERT_EQ(X.cols(), B.cols());
          ASSERT_TRUE(X.allFinite());
          const DenseMat Aref = dense * scale;
          const DenseMat Xref = db::exact::exact_solution(U, B);
          EXPECT_WITHIN(rel(Aref * X, B), tol);
          EXPECT_WITHIN(rel(X, Xref), forward);
          // One column at a time is as exact as the block solve.
          DenseMat x1;
          solver->solve(B.col(1), x1);
          EXPECT_WITHIN(rel(x1, Xref.col(1)), forward);
        }
        const db::FactorStats st = solver->stats();
        EXPECT_EQ(st.n, std::size_t(upper.rows()));
        EXPECT_EQ(st.nnz_matrix, std::size_t(upper.nonZeros()));
        EXPECT_GT(st.factor_bytes, 0u);
        if (iterative()) {
          EXPECT_GT(st.iterations, 0);
          EXPECT_LE(st.achieved_tolerance, 1e-12);
        } else {
          EXPECT_GE(st.nnz_factor, std::size_t(upper.rows()));
        }
        if (si.family != "dense" && !iterative()) {
          EXPECT_FALSE(st.ordering_used.empty());
        }
      }
  }
}

//! Indefinite: flip the sign of one diagonal entry (then e_k^T A e_k < 0).
TEST_P(Conformance, IndefiniteIsRejectedOrFinite) {
  std::mt19937 rng(3);
  SpMat A = normal_equations(mesh_laplacian(7, 6, true, rng), 3, rng);
  A.coeffRef(10, 10) = -A.coeffRef(10, 10);
  const SpMat upper = upper_of(A);
  auto solver = db::make_solver(GetParam(), options("default", 1));
  solver->analyze(upper);
  if (info().requires_spd) {
    EXPECT_THROW(solver->factorize(upper), db::SolverError);
    return;
  }
  try {  // LU-type / iterative: may solve it, but never hand back NaN
    solver->factorize(upper);
    DenseMat X;
    solver->solve(random_rhs(upper.rows(), 2, rng), X);
    EXPECT_TRUE(X.allFinite());
  } catch (const db::SolverError&) {
  }
}

//! Singular: the bi-Laplacian of a closed mesh without constraints (constants in the null space),
//! and a matrix with an empty row/column (exact zero pivot).
TEST_P(Conformance, SingularIsRejectedOrFinite) {
  std::mt19937 rng(4);
  const SpMat L = mesh_laplacian(7, 6, true, rng);
  SpMat zero_col = normal_equations(L, 3, rng);
  for (int j = 0; j < zero_col.outerSize(); ++j)
    for (SpMat::InnerIterator it(zero_col, j); it; ++it)
      if (it.row() == 5 || j == 5) it.valueRef() = 0;
  for (const SpMat& A : {SpMat(SpMat(L.transpose()) * L), zero_col}) {
    const SpMat upper = upper_of(A);
    auto solver = db::make_solver(GetParam(), options("default", 1));
    solver->analyze(upper);
    if (info().requires_spd) {
      EXPECT_THROW(solver->factorize(upper), db::SolverError);
      continue;
    }
    try {
      solver->factorize(upper);
      DenseMat X;
      solver->solve(random_rhs(upper.rows(), 2, rng), X);
      EXPECT_TRUE(X.allFinite());
    } catch (const db::SolverError&) {
    }
  }
}

TEST_P(Conformance, NonFiniteInputIsRejected) {
  std::mt19937 rng(5);
  SpMat upper = upper_of(normal_equations(mesh_laplacian(6, 6, true, rng), 3, rng));
  auto solver = db::make_solver(GetParam(), options("default", 1));
  solver->analyze(upper);
  upper.valuePtr()[7] = std::nan("");
  EXPECT_THROW(solver->factorize(upper), db::SolverError);
}

// The per-frame path: right-hand sides that differ from a base only in a few rows (as when only the handle
// moves) must give what a full solve gives; a change outside those rows must still be solved correctly.
TEST_P(Conformance, SolveChangedMatchesSolve) {
  std::mt19937 rng(15);
  const SpMat full = kron3(normal_equations(mesh_laplacian(14, 12, true, rng), 4, rng));
  const SpMat upper = upper_of(full);
  db::SolverOptions o;
  o.block_size = 3;
  o.tolerance = 1e-12;
  auto solver = db::make_solver(GetParam(), o);
  solver->factorize(upper);
  const int r = 2;
  const DenseMat B0 = random_rhs(upper.rows(), r, rng);
  const std::vector<int> rows = {30, 31, 32, 301, 477};
  solver->set_base_rhs(B0, rows);
  // Each path against the exact solution: the shortcut and the full solve round differently.
  const double tol = bound(db::exact::condition_number(upper));
  for (int frame = 0; frame < 3; ++frame) {
    DenseMat B = B0;
    for (int i : rows) B.row(i) += random_rhs(1, r, rng);
    DenseMat X, Xs;
    solver->solve_changed(B, X);
    solver->solve(B, Xs);
    const DenseMat Xref = db::exact::exact_solution(upper, B, 3);
    EXPECT_WITHIN(rel(X, Xref), tol) << "frame " << frame;
    EXPECT_WITHIN(rel(Xs, Xref), tol) << "frame " << frame;
    EXPECT_WITHIN(rel(DenseMat(full * X), B), iterative() ? 1e-6 : 1e-10);
  }
  DenseMat B = B0;
  B(100, 0) += 1.0;  // not a declared row: solved in full
  const DenseMat Xref = db::exact::exact_solution(upper, B, 3);
  DenseMat X, Xs;
  solver->solve_changed(B, X);
  solver->solve(B, Xs);
  EXPECT_WITHIN(rel(X, Xref), tol);
  EXPECT_WITHIN(rel(Xs, Xref), tol);
  // One right-hand side where the base had two: no shortcut, still right.
  DenseMat x1;
  solver->solve_changed(B.col(0), x1);
  EXPECT_WITHIN(rel(x1, Xref.col(0)), tol);
}

// factorize_consuming: the same factor as factorize, and the matrix is left empty, also after a failure.
TEST_P(Conformance, FactorizeConsumingMatchesFactorize) {
  std::mt19937 rng(16);
  const SpMat full = kron3(normal_equations(mesh_laplacian(9, 8, true, rng), 3, rng));
  db::SolverOptions o;
  o.block_size = 3;
  o.tolerance = 1e-12;
  const DenseMat B = random_rhs(full.rows(), 2, rng);
  auto a = db::make_solver(GetParam(), o), c = db::make_solver(GetParam(), o);
  a->factorize(upper_of(full));
  SpMat consumed = upper_of(full);
  c->factorize_consuming(consumed);
  EXPECT_EQ(consumed.nonZeros(), 0);
  EXPECT_EQ(consumed.rows(), 0);
  DenseMat Xa, Xc;
  a->solve(B, Xa);
  c->solve(B, Xc);
  const SpMat upper = upper_of(full);
  const DenseMat Xref = db::exact::exact_solution(upper, B, 3);
  const double tol = bound(db::exact::condition_number(upper));
  EXPECT_WITHIN(rel(Xa, Xref), tol);
  EXPECT_WITHIN(rel(Xc, Xref), tol);
  if (info().requires_spd) {
    SpMat bad = upper_of(full);
    bad.coeffRef(7, 7) = -1.0;
    EXPECT_THROW(db::make_solver(GetParam(), o)->factorize_consuming(bad), db::SolverError);
    EXPECT_EQ(bad.nonZeros(), 0);
  }
}

// factorize_dense (the dense build's input): dense backends solve as from the sparse upper triangle and report
// the same factor; the others refuse it with an Error naming the dense backends and leave the matrix empty.
TEST_P(Conformance, DenseInputOnlyForDenseBackends) {
  std::mt19937 rng(17);
  const SpMat full = normal_equations(mesh_laplacian(7, 6, true, rng), 3, rng);
  const DenseMat B = random_rhs(full.rows(), 3, rng);
  auto sparse = db::make_solver(GetParam(), options("default", 1)), dense = db::make_solver(GetParam(), options("default", 1));
  sparse->factorize(upper_of(full));
  DenseMat A = DenseMat(full);
  if (info().family != "dense") {
    try {
      dense->factorize_dense(A);
      FAIL() << "expected db::Error";
    } catch (const db::Error& e) {
      for (const std::string& name : db::solver_names()) {
        if (db::solver_info(name).family == "dense") {
          EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
        }
      }
    }
    EXPECT_EQ(A.size(), 0);
    return;
  }
  dense->factorize_dense(A);
  EXPECT_EQ(A.size(), 0);
  DenseMat Xs, Xd;
  sparse->solve(B, Xs);
  dense->solve(B, Xd);
  const DenseMat Xref = db::exact::exact_solution(upper_of(full), B);
  const double tol = bound(db::exact::condition_number(upper_of(full)));
  EXPECT_WITHIN(rel(Xs, Xref), tol);
  EXPECT_WITHIN(rel(Xd, Xref), tol);
  const db::FactorStats ss = sparse->stats(), sd = dense->stats();
  const std::size_t n = std::size_t(full.rows());
  EXPECT_EQ(sd.n, n);
  EXPECT_EQ(sd.nnz_matrix, n * (n + 1) / 2);  // the dense matrix's upper triangle
  EXPECT_EQ(sd.nnz_factor, ss.nnz_factor);
  EXPECT_EQ(sd.flops, ss.flops);
  EXPECT_EQ(sd.factor_bytes, ss.factor_bytes);
  EXPECT_NEAR(sd.min_pivot_ratio, ss.min_pivot_ratio, 2 * pivot_ratio_error(n));
  if (info().requires_spd) {
    DenseMat bad = DenseMat(full);
    bad(4, 4) = -1.0;
    EXPECT_THROW(dense->factorize_dense(bad), db::SolverError);
    DenseMat X;
    EXPECT_THROW(dense->solve(B, X), db::SolverError) << "no factor after a failure";
  }
  DenseMat nan = DenseMat(full), wide = DenseMat::Ones(4, 5);
  nan(3, 2) = std::nan("");
  EXPECT_THROW(dense->factorize_dense(nan), db::SolverError);
  EXPECT_EQ(nan.size(), 0);
  EXPECT_THROW(dense->factorize_dense(wide), db::SolverError);
  // Singular: the bi-Laplacian of a closed mesh without constraints; every dense backend tests for it (pivots
  // or LAPACK's condition estimate).
  const SpMat L = mesh_laplacian(7, 6, true, rng);
  DenseMat singular = DenseMat(SpMat(L.transpose()) * L);
  EXPECT_THROW(dense->factorize_dense(singular), db::SolverError);
}

//! Smallest L_kk^2 / A_kk of a dense Cholesky in the natural order: what a Cholesky backend's min_pivot_ratio
//! must be in that order.
double dense_min_pivot_ratio(const DenseMat& A) {
  const DenseMat L = A.llt().matrixL();
  double r = 1e300;
  for (Eigen::Index k = 0; k < A.rows(); ++k) r = std::min(r, L(k, k) * L(k, k) / A(k, k));
  return r;
}

// What each family reports in FactorStats (linear_solver.h), against the matrix: sizes, factor counts within
// the bounds of its factor type, the pivot ratio where the backend tests pivots (a dense Cholesky's, in the
// natural order), nothing on disk.
TEST_P(Conformance, StatsDescribeTheFactor) {
  std::mt19937 rng(19);
  const SpMat full = normal_equations(mesh_laplacian(8, 7, true, rng), 3, rng);
  const SpMat upper = upper_of(full);
  const std::size_t n = std::size_t(full.rows()), tri = n * (n + 1) / 2;
  const db::SolverInfo si = info();
  const bool natural = std::find(si.orderings.begin(), si.orderings.end(), "natural") != si.orderings.end();
  auto s = db::make_solver(GetParam(), options(natural ? "natural" : "default", 1));
  s->analyze(upper);
  s->factorize(upper);
  DenseMat X;
  s->solve(random_rhs(full.rows(), 1, rng), X);  // iterative backends report on solve
  const db::FactorStats st = s->stats();
  EXPECT_EQ(st.n, n);
  EXPECT_EQ(st.nnz_matrix, std::size_t(upper.nonZeros()));
  EXPECT_FALSE(st.factor_on_disk);
  EXPECT_FALSE(st.ordering_used.empty());
  if (si.family == "dense") {
    EXPECT_EQ(st.ordering_used, "none");
    EXPECT_TRUE(st.nnz_factor == tri || st.nnz_factor == n * n) << st.nnz_factor;  // triangle; LU: L and U
    const double cube = double(n) * double(n) * double(n);
    EXPECT_DOUBLE_EQ(st.flops, st.nnz_factor == tri ? cube / 3 : 2 * cube / 3);
    EXPECT_GE(st.factor_bytes, n * n * sizeof(double));
  } else if (si.family == "sparse-cholesky") {
    EXPECT_GE(st.nnz_factor, n);
    EXPECT_LE(st.nnz_factor, tri);
    EXPECT_GE(st.flops, double(st.nnz_factor));  // sum of squared column counts
    const std::size_t entry = GetParam() == "multifrontal_mixed" ? sizeof(float) : sizeof(double);
    EXPECT_GE(st.factor_bytes, st.nnz_factor * entry);
  } else if (si.family == "sparse-lu") {
    EXPECT_GE(st.nnz_factor, n);
    EXPECT_LE(st.nnz_factor, n * n);
    EXPECT_GE(st.factor_bytes, st.nnz_factor * sizeof(double));
  } else {
    ASSERT_EQ(si.family, "iterative");
    EXPECT_EQ(st.nnz_factor, 0u);
    EXPECT_EQ(st.flops, 0);
    EXPECT_GT(st.iterations, 0);
    EXPECT_LE(st.achieved_tolerance, 1e-12);
  }
  if (si.requires_spd) {  // the Cholesky-type backends test their pivots and report the smallest ratio
    ASSERT_TRUE(natural);
    const double ref = dense_min_pivot_ratio(DenseMat(full));
    if (si.keeps_natural_order) {
      EXPECT_NEAR(st.min_pivot_ratio, ref, 2 * pivot_ratio_error(n));  // both computed: each within the bound
    } else {  // in its own order: every pivot of D^-1/2 A D^-1/2 lies between its smallest eigenvalue and 1
      const db::DenseVec d = DenseMat(full).diagonal().cwiseSqrt().cwiseInverse();
      const DenseMat S = d.asDiagonal() * DenseMat(full) * d.asDiagonal();
      const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<DenseMat>(S).eigenvalues();
      // less the pivot's rounding and the eigenvalue's (backward stable: within n eps ||S|| of S's)
      EXPECT_GE(st.min_pivot_ratio, ev(0) - pivot_ratio_error(n) * (1 + ev(ev.size() - 1)));
    }
    EXPECT_LE(st.min_pivot_ratio, 1.0);
  } else {
    EXPECT_EQ(st.min_pivot_ratio, 0) << "no pivot test, no ratio";
  }
}

TEST_P(Conformance, MisuseIsReported) {
  std::mt19937 rng(6);
  const SpMat upper = upper_of(normal_equations(mesh_laplacian(6, 6, true, rng), 3, rng));
  auto solver = db::make_solver(GetParam(), options("default", 1));
  DenseMat X;
  EXPECT_THROW(solver->solve(random_rhs(upper.rows(), 1, rng), X), db::SolverError);  // nothing factored
  solver->analyze(upper);
  solver->factorize(upper);
  EXPECT_THROW(solver->solve(random_rhs(upper.rows() + 1, 1, rng), X), db::SolverError);  // wrong size
  EXPECT_THROW(db::make_solver(GetParam(), options("no-such-ordering", 1)), db::Error);
}

INSTANTIATE_TEST_SUITE_P(AllBackends, Conformance, ::testing::ValuesIn(db::solver_names()),
                         [](const ::testing::TestParamInfo<std::string>& p) { return p.param; });

TEST(Registry, UnknownNameListsValidOnes) {
  try {
    db::make_solver("no_such_solver");
    FAIL() << "expected db::Error";
  } catch (const db::SolverError&) {
    FAIL() << "an unknown name is a usage error, not a solver failure";
  } catch (const db::Error& e) {
    EXPECT_NE(std::string(e.what()).find("cholmod_supernodal"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(db::solver_names().empty());
}

TEST(Cholmod, BlockOrderingMatchesScalarOrdering) {
  std::mt19937 rng(8);
  const SpMat upper = upper_of(kron3(normal_equations(mesh_laplacian(10, 9, true, rng), 4, rng)));
  const DenseMat B = random_rhs(upper.rows(), 3, rng);
  // Each order against the exact solution: two orders round differently.
  const DenseMat Xref = db::exact::exact_solution(upper, B, 3);
  const double tol = db::exact::solve_bound(db::exact::condition_number(upper));
  for (const char* name : {"cholmod_supernodal", "cholmod_simplicial_ldlt"})
    for (const std::string ordering : {"amd", "metis", "nesdis"}) {
      DenseMat X[2];
      for (int block : {1, 3}) {
        db::SolverOptions o;
        o.ordering = ordering;
        o.block_size = block;
        auto s = db::make_solver(name, o);
        s->analyze(upper);
        s->factorize(upper);
        s->solve(B, X[block == 3]);
        EXPECT_EQ(s->stats().ordering_used, block == 3 ? ordering + "-block3" : ordering) << name;
        EXPECT_WITHIN(rel(X[block == 3], Xref), tol) << name << " " << ordering << " block " << block;
      }
    }
  db::SolverOptions o;
  o.block_size = 3;  // "default" on a small system: block AMD (CHOLMOD's rule only tries METIS at high fill)
  auto s = db::make_solver("cholmod_supernodal", o);
  s->analyze(upper);
  EXPECT_EQ(s->stats().ordering_used, "amd-block3");
  o.block_size = 4;  // n is not a multiple of 4: scalar ordering
  s = db::make_solver("cholmod_supernodal", o);
  s->analyze(upper);
  EXPECT_EQ(s->stats().ordering_used.find("block"), std::string::npos);
}

TEST(Cholmod, NotPositiveDefiniteNamesTheColumn) {
  std::mt19937 rng(9);
  SpMat A = normal_equations(mesh_laplacian(6, 6, true, rng), 3, rng);
  A.coeffRef(3, 3) = -1;
  auto s = db::make_solver("cholmod_supernodal");
  try {
    s->factorize(upper_of(A));  // factorize without analyze analyzes implicitly
    FAIL() << "expected SolverError";
  } catch (const db::SolverError& e) {
    EXPECT_NE(std::string(e.what()).find("not positive definite (failed at column"), std::string::npos) << e.what();
  }
}

TEST(Cholmod, DifferentPatternNeedsAnalyze) {
  std::mt19937 rng(10);
  const SpMat a = upper_of(normal_equations(mesh_laplacian(6, 6, true, rng), 3, rng));
  const SpMat b = upper_of(normal_equations(mesh_laplacian(6, 7, true, rng), 3, rng));
  auto s = db::make_solver("cholmod_supernodal");
  s->analyze(a);
  EXPECT_THROW(s->factorize(b), db::SolverError);
}

//! DEFORMBENCH_THREADS for one scope (the multifrontal backend reads it at analyze()), the caller's restored after.
using ThreadsEnv = db::test::WorkerThreads;

// Large enough that the assembly tree has top supernodes and several subtrees per thread; on every thread count,
// as CHOLMOD, the answer must be the exact one up to the rounding the system's conditioning allows (the thread count
// changes the order of the sums, so the solves are not compared with each other), for scalar and 3x3-block systems,
// with a given (natural) order and the backend's own.
TEST(Multifrontal, ThreadCountsAndBackendsAgree) {
  std::mt19937 rng(13);
  const SpMat scalar = normal_equations(mesh_laplacian(40, 35, true, rng), 6, rng);
  for (const auto& [full, block] : {std::pair<SpMat, int>{scalar, 1}, {kron3(scalar), 3}}) {
    const SpMat upper = upper_of(full);
    const DenseMat B = random_rhs(upper.rows(), 3, rng);
    const DenseMat Xref = db::exact::exact_solution(upper, B, block);
    const double tol = db::exact::solve_bound(db::exact::condition_number(upper));
    for (const std::string ordering : {"natural", "metis", "amd"}) {
      SCOPED_TRACE(fmt::format("block {} ordering {}", block, ordering));
      db::SolverOptions o;
      o.ordering = ordering;
      o.block_size = block;
      DenseMat X[3];
      db::FactorStats st[3];
      for (int threads : {1, 2, 3}) {
        ThreadsEnv env(threads);
        auto s = db::make_solver("multifrontal", o);
        s->analyze(upper);
        s->factorize(upper);
        s->solve(B, X[threads - 1]);
        st[threads - 1] = s->stats();
        DenseMat x1;  // one right-hand side takes the single-column kernels
        s->solve(B.col(2), x1);
        EXPECT_WITHIN(rel(x1, Xref.col(2)), tol) << threads << " thread(s)";
        EXPECT_WITHIN(rel(X[threads - 1], Xref), tol) << threads << " thread(s)";
      }
      EXPECT_EQ(st[1].nnz_factor, st[0].nnz_factor);
      EXPECT_GT(st[0].flops, 0);
      EXPECT_GT(st[0].workspace_bytes, 0u);  // the update matrices' peak
      EXPECT_GE(st[0].nnz_factor, std::size_t(upper.nonZeros()));
      auto ref = db::make_solver("cholmod_supernodal", o);
      ref->factorize(upper);
      DenseMat Xc;
      ref->solve(B, Xc);
      EXPECT_WITHIN(rel(Xc, Xref), tol);
      EXPECT_WITHIN(rel(DenseMat(full * X[0]), B), 1e-10);
    }
  }
}

// Many right-hand sides at once (the handle-mode precompute's: LAP 7, TF 13, per-vertex drags hundreds) take the
// blocked path, a dgemm per panel (triangular_solve.cpp): each column must be as exact as its own single-column
// solve (the hand-written kernels; the two round differently, so both are held to the exact solution), on one and
// two threads, in memory and out of core, for scalar and 3x3-block systems.
TEST(Multifrontal, ManyRightHandSidesMatchColumnByColumn) {
  std::mt19937 rng(19);
  const SpMat scalar = normal_equations(mesh_laplacian(40, 35, true, rng), 6, rng);
  for (const auto& [full, block] : {std::pair<SpMat, int>{scalar, 1}, {kron3(scalar), 3}}) {
    const SpMat upper = upper_of(full);
    const DenseMat B = random_rhs(upper.rows(), 40, rng);
    const DenseMat Xref = db::exact::exact_solution(upper, B, block);
    const double tol = db::exact::solve_bound(db::exact::condition_number(upper));
    for (int threads : {1, 2})
      for (bool on_disk : {false, true}) {
        SCOPED_TRACE(fmt::format("block {}, {} thread(s), {}", block, threads, on_disk ? "out of core" : "in memory"));
        ThreadsEnv env(threads);
        db::SolverOptions o;
        o.block_size = block;
        if (on_disk) o.factor_dir = std::filesystem::temp_directory_path().string();
        auto s = db::make_solver("multifrontal", o);
        s->analyze(upper);
        s->factorize(upper);
        for (int r : {5, 7, 13, 40}) {
          DenseMat X;
          s->solve(B.leftCols(r), X);
          for (int c = 0; c < r; ++c) {
            DenseMat x;
            s->solve(B.col(c), x);
            EXPECT_WITHIN(rel(X.col(c), Xref.col(c)), tol) << r << " right-hand sides, column " << c;
            EXPECT_WITHIN(rel(x, Xref.col(c)), tol) << "column " << c << " alone";
          }
        }
      }
  }
}

// Large enough (over 16 MB of values) that the multifrontal backend hands the consumed matrix's pages back
// subtree by subtree: the factor must not notice (on one thread the same solution as from the untouched matrix,
// bitwise; on any count the exact one up to the rounding the system's conditioning allows).
TEST(Multifrontal, ConsumingReleasesWithoutChangingTheFactor) {
  std::mt19937 rng(17);
  const SpMat full = kron3(normal_equations(mesh_laplacian(170, 150, true, rng), 8, rng));
  ASSERT_GT(std::size_t(upper_of(full).nonZeros()) * sizeof(double), std::size_t(16) << 20);
  const DenseMat B = random_rhs(full.rows(), 1, rng);
  db::SolverOptions o;
  o.block_size = 3;
  const SpMat upper = upper_of(full);
  const DenseMat Xref = db::exact::exact_solution(upper, B, 3);
  const double tol = db::exact::solve_bound(db::exact::condition_number(upper));
  DenseMat Xa;
  {
    ThreadsEnv env(1);
    auto a = db::make_solver("multifrontal", o);
    a->factorize(upper);
    a->solve(B, Xa);
  }
  for (int threads : {1, 2}) {
    ThreadsEnv env(threads);
    auto c = db::make_solver("multifrontal", o);
    SpMat consumed = upper;
    c->factorize_consuming(consumed);
    EXPECT_EQ(consumed.nonZeros(), 0);
    DenseMat Xc;
    c->solve(B, Xc);
    // Xa ran on one thread; two threads sum in another order (this torus system is ill-conditioned).
    if (threads == 1) {
      EXPECT_TRUE(Xc == Xa);
    }
    EXPECT_WITHIN(rel(Xc, Xref), tol) << threads << " thread(s)";
    EXPECT_WITHIN(rel(DenseMat(full * Xc), B), 1e-9);
  }
}

// Out of core: the factor lives in a scratch file and only the supernode at work is resident. The same
// factorization (one thread: bitwise), a factor that stays out of the resident set, and clear errors for a
// backend that cannot and for a directory that does not exist.
TEST(Multifrontal, OutOfCoreFactorMatchesInMemoryAndIsNotResident) {
  std::mt19937 rng(18);
  const SpMat full = kron3(normal_equations(mesh_laplacian(130, 120, true, rng), 8, rng));
  const SpMat upper = upper_of(full);
  const DenseMat B = random_rhs(full.rows(), 3, rng);
  db::SolverOptions o;
  o.block_size = 3;
  db::SolverOptions d = o;
  d.factor_dir = std::filesystem::temp_directory_path().string();
  std::vector<DenseMat> solutions;  // held to the exact solution after the resident-set measurements
  for (int threads : {1, 2}) {
    ThreadsEnv env(threads);
    DenseMat X[2];
    std::size_t grew[2], factor_bytes = 0;
    for (int k = 0; k < 2; ++k) {
      auto s = db::make_solver("multifrontal", k == 0 ? o : d);
      s->analyze(upper);
      const std::size_t before = db::current_rss_bytes();
      s->factorize(upper);
      s->solve(B, X[k]);
      grew[k] = db::current_rss_bytes() - std::min(before, db::current_rss_bytes());
      EXPECT_EQ(s->stats().factor_on_disk, k == 1);
      factor_bytes = s->stats().factor_bytes;
    }
    ASSERT_GT(factor_bytes, std::size_t(48) << 20) << factor_bytes;  // large enough to tell resident from not
    if (threads == 1) {
      EXPECT_TRUE(X[1] == X[0]);
    }
    solutions.insert(solutions.end(), {X[0], X[1]});  // two threads: the top phase adds subtree roots as they come
    EXPECT_WITHIN(rel(DenseMat(full * X[1]), B), 1e-9);
    // Out of core what stays is heap the threads' allocators keep (update matrices), tens of MB here.
    // Under AddressSanitizer its quarantine keeps freed memory resident for later allocations, so the resident set
    // does not grow with them (with ASAN_OPTIONS=quarantine_size_mb=0 these checks hold there too).
#ifndef __SANITIZE_ADDRESS__
    EXPECT_GT(grew[0], factor_bytes * 9 / 10) << "in memory the factor is resident; " << threads << " thread(s)";
    EXPECT_LT(grew[1], factor_bytes / 2) << "out of core it is not; " << threads << " thread(s)";
#else
    (void)grew;
#endif
  }
  const DenseMat Xref = db::exact::exact_solution(upper, B, 3);
  const double tol = db::exact::solve_bound(db::exact::condition_number(upper));
  for (std::size_t k = 0; k < solutions.size(); ++k)
    EXPECT_WITHIN(rel(solutions[k], Xref), tol) << 1 + k / 2 << " thread(s), " << (k % 2 ? "out of core" : "in memory");
  EXPECT_THROW(db::make_solver("cholmod_supernodal", d), db::Error);
  db::SolverOptions missing = o;
  missing.factor_dir = (std::filesystem::temp_directory_path() / "deformbench-no-such-dir").string();
  auto s = db::make_solver("multifrontal", missing);
  try {
    s->factorize(upper);
    FAIL() << "expected an error for a missing directory";
  } catch (const db::Error& e) {
    EXPECT_NE(std::string(e.what()).find("deformbench-no-such-dir"), std::string::npos) << e.what();
  }
}

// SolverOptions::memory_budget: a backend that checks it (SolverInfo::checks_memory) refuses a factorization whose
// factor and update matrices would not fit beside what the process holds, with BudgetError and before factoring
// (a solve then finds nothing factored), and factors within a budget that holds them; out of core the factor is
// not resident and is not checked. The other backends ignore the budget (their callers predict the peak).
TEST(MemoryBudget, CheckingBackendsRefuseBeforeFactoringAndFactorWithinIt) {
  std::mt19937 rng(19);
  const SpMat full = kron3(normal_equations(mesh_laplacian(60, 50, true, rng), 8, rng));
  const SpMat upper = upper_of(full);
  const DenseMat B = random_rhs(full.rows(), 2, rng);
  const auto options = [&](std::size_t budget_above_resident, bool on_disk) {
    db::SolverOptions o;
    o.block_size = 3;
    o.memory_budget = db::current_rss_bytes() + budget_above_resident;
    if (on_disk) o.factor_dir = std::filesystem::temp_directory_path().string();
    return o;
  };
  const std::size_t tight = std::size_t(1) << 20, ample = std::size_t(1) << 30;
  int checking = 0;
  for (const std::string& name : db::solver_names()) {
    const db::SolverInfo info = db::solver_info(name);
    if (!info.checks_memory) continue;
    ++checking;
    auto refused = db::make_solver(name, options(tight, false));
    refused->analyze(upper);
    ASSERT_GT(refused->stats().factor_bytes, tight) << name;  // the tight budget cannot hold the factor
    DenseMat X;
    EXPECT_THROW(refused->factorize(upper), db::BudgetError) << name;
    EXPECT_THROW(refused->solve(B, X), db::Error) << name << ": nothing is factored";
    std::vector<db::SolverOptions> fits;
    fits.push_back(options(ample, false));
    if (info.out_of_core) fits.push_back(options(tight, true));
    for (const db::SolverOptions& o : fits) {
      auto s = db::make_solver(name, o);
      s->analyze(upper);
      s->factorize(upper);
      s->solve(B, X);
      EXPECT_WITHIN(rel(DenseMat(full * X), B), 1e-9) << name << (o.factor_dir.empty() ? "" : ", out of core");
    }
  }
  auto other = db::make_solver("cholmod_supernodal", options(tight, false));  // ignores it
  other->analyze(upper);
  other->factorize(upper);
  EXPECT_TRUE(db::solver_info("multifrontal").checks_memory);
  EXPECT_EQ(checking, 3);  // multifrontal, its mixed and its refined variants
}

// A regular matrix whose smallest pivot is under the singular-input bound 10 n eps: a 2 x 2 block
// [1, 1 - e; 1 - e, 1] (pivot 2e - e^2 = 2e-13 of its diagonal) in a 1000-unknown identity (bound 2.2e-12).
// The pivot test rejects it by default; turned off, the factorization goes through, reports the pivot, and
// solves (x = 1 / (2 - e) on both unknowns for b = (1, 1)).
TEST(PivotTest, RegularButBelowTheBoundIsRejectedOnlyWhenAsked) {
  const int n = 1000;
  const double e = 1e-13;
  Triplets t;
  for (int i = 0; i < n; ++i) t.emplace_back(i, i, 1.0);
  t.emplace_back(0, 1, 1.0 - e);
  SpMat upper(n, n);
  upper.setFromTriplets(t.begin(), t.end());
  ASSERT_LT(2 * e, db::singular_pivot_bound(n));
  DenseMat B = DenseMat::Ones(n, 1);
  for (const std::string backend : {"multifrontal", "cholmod_supernodal"}) {
    SCOPED_TRACE(backend);
    db::SolverOptions o;
    o.ordering = "natural";
    auto strict = db::make_solver(backend, o);
    strict->analyze(upper);
    EXPECT_THROW(strict->factorize(upper), db::SolverError);
    o.pivot_singularity_test = false;
    auto relaxed = db::make_solver(backend, o);
    relaxed->analyze(upper);
    relaxed->factorize(upper);
    EXPECT_NEAR(relaxed->stats().min_pivot_ratio, 2 * e, 2e-3 * 2 * e);
    DenseMat X;
    relaxed->solve(B, X);
    EXPECT_NEAR(X(0, 0), 1 / (2 - e), 1e-9);
    EXPECT_NEAR(X(1, 0), 1 / (2 - e), 1e-9);
    EXPECT_EQ(X(2, 0), 1.0);
  }
}

TEST(Multifrontal, NotPositiveDefiniteNamesTheColumn) {
  std::mt19937 rng(14);
  SpMat A = normal_equations(mesh_laplacian(30, 30, true, rng), 3, rng);
  A.coeffRef(700, 700) = -1;
  for (int threads : {1, 2}) {
    ThreadsEnv env(threads);
    auto s = db::make_solver("multifrontal");
    try {
      s->factorize(upper_of(A));
      FAIL() << "expected SolverError";
    } catch (const db::SolverError& e) {
      EXPECT_NE(std::string(e.what()).find("not positive definite (failed at column"), std::string::npos) << e.what();
    }
    DenseMat X;
    EXPECT_THROW(s->solve(DenseMat::Ones(A.rows(), 1), X), db::SolverError);  // no factor after a failure
  }
}

// Supernodes wider than a factor panel (256 columns) and update matrices wider than an update panel (128):
// an arrow matrix whose first `leaves` columns each couple to all of the last `dense` ones, natural order, so
// the leaves carry `dense`-row update matrices and the last columns form one supernode of several panels.
// Checked against the exact solution (exact_reference.h), on one and two threads; a failed pivot in the last panel
// is named.
TEST(Multifrontal, WidePanelsMatchDense) {
  std::mt19937 rng(15);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int leaves = 40, dense = 600, n = leaves + dense;
  DenseMat M = DenseMat::Zero(n, n);
  for (int j = 0; j < leaves; ++j)
    for (int i = leaves; i < n; ++i) M(i, j) = M(j, i) = u(rng);
  for (int j = leaves; j < n; ++j)
    for (int i = leaves; i < j; ++i) M(i, j) = M(j, i) = 0.05 * u(rng);
  for (int i = 0; i < n; ++i) M(i, i) = 2.0 * n;
  const SpMat full = M.sparseView();
  const DenseMat B = random_rhs(n, 13, rng);  // more than the row-vector kernel's four right-hand sides
  const DenseMat Xref = db::exact::exact_solution(upper_of(full), B);
  const double tol = db::exact::solve_bound(db::exact::condition_number(upper_of(full)));
  db::SolverOptions o;
  o.ordering = "natural";
  for (int threads : {1, 2}) {
    ThreadsEnv env(threads);
    auto s = db::make_solver("multifrontal", o);
    s->factorize(upper_of(full));
    DenseMat X;
    s->solve(B, X);
    EXPECT_WITHIN(rel(X, Xref), tol) << threads << " thread(s)";
    for (int r : {1, 2, 3, 4, 13}) {  // the backward kernels' special cases, and the blocked path's (13)
      DenseMat Xr;
      s->solve(B.leftCols(r), Xr);
      EXPECT_WITHIN(rel(Xr, Xref.leftCols(r)), tol) << r << " right-hand side(s), " << threads << " thread(s)";
    }
    // Stored entries: the lower triangle at most (relaxed amalgamation may merge the leaves), never the square.
    EXPECT_LE(s->stats().nnz_factor, std::size_t(n) * (n + 1) / 2);
    EXPECT_GE(s->stats().nnz_factor, std::size_t(n) * (n + 1) / 2 - std::size_t(leaves) * (leaves - 1) / 2);
    DenseMat X1;
    s->solve_changed(B, X1);  // no base right-hand side: a full solve
    EXPECT_WITHIN(rel(X1, Xref), tol);
  }
  DenseMat bad = M;
  bad(n - 5, n - 5) = -1.0;  // column n - 5 lies in the third panel of the last supernode
  auto s = db::make_solver("multifrontal", o);
  try {
    s->factorize(upper_of(SpMat(bad.sparseView())));
    FAIL() << "expected SolverError";
  } catch (const db::SolverError& e) {
    EXPECT_NE(std::string(e.what()).find(fmt::format("failed at column {} of {}", n - 5, n)), std::string::npos) << e.what();
  }
}

TEST(Dense, RefusesHugeSystemsBeforeAllocating) {
  SpMat I(16001, 16001);
  I.setIdentity();
  int dense = 0;
  for (const std::string& name : db::solver_names())
    if (db::solver_info(name).family == "dense") {
      EXPECT_THROW(db::make_solver(name)->analyze(I), db::BudgetError) << name;
      ++dense;
    }
  EXPECT_GE(dense, 4);  // dense_llt, lapack_potrf, dense_ldlt_bk, dense_lu
}

//! [L; w S]: mesh Laplacian rows plus weighted constraint rows (m > n, full column rank).
SpMat least_squares_matrix(const SpMat& L, const std::vector<int>& constrained, double w) {
  Triplets t;
  for (int j = 0; j < L.outerSize(); ++j)
    for (SpMat::InnerIterator it(L, j); it; ++it) t.emplace_back(it.row(), j, it.value());
  for (std::size_t k = 0; k < constrained.size(); ++k) t.emplace_back(L.rows() + Eigen::Index(k), constrained[k], w);
  SpMat A(L.rows() + Eigen::Index(constrained.size()), L.cols());
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

// Against the exact least-squares solution (the normal equations formed and solved in long double), under the
// bound of a solve of the normal matrix's condition cond(A)^2: QR's error is at most of the order eps (cond(A) +
// cond(A)^2 ||r|| / (||A|| ||x||)) and the normal equations' eps cond(A)^2.
TEST(SpqrLeastSquares, MatchesNormalEquations) {
  std::mt19937 rng(11);
  for (const bool torus : {true, false}) {
    const SpMat A = least_squares_matrix(mesh_laplacian(11, 9, torus, rng), {0, 17, 50, 98}, 2.0);
    const DenseMat B = random_rhs(A.rows(), 3, rng);
    db::SpqrLeastSquares qr;
    qr.factorize(A);
    DenseMat X;
    qr.solve(B, X);
    const DenseMat Ad = DenseMat(A);
    using LongMat = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
    const LongMat Al = Ad.cast<long double>();
    const DenseMat Xref = (Al.transpose() * Al).llt().solve(Al.transpose() * B.cast<long double>()).cast<double>();
    const SpMat N = upper_of(SpMat(A.transpose()) * A);
    const double tol = db::exact::solve_bound(db::exact::condition_number(N));
    EXPECT_WITHIN(rel(X, Xref), tol);
    // The same answer through the registered normal-equation backend.
    auto chol = db::make_solver("cholmod_supernodal");
    chol->factorize(N);
    DenseMat Xn;
    chol->solve(DenseMat(Ad.transpose() * B), Xn);
    EXPECT_WITHIN(rel(Xn, Xref), tol);
    const db::FactorStats st = qr.stats();
    EXPECT_EQ(st.n, std::size_t(A.cols()));
    EXPECT_GE(st.nnz_factor, std::size_t(A.cols()));
    EXPECT_GT(st.flops, 0);
    EXPECT_GT(st.factor_bytes, 0u);
    EXPECT_FALSE(st.ordering_used.empty());
  }
}

TEST(SpqrLeastSquares, RejectsMisuse) {
  std::mt19937 rng(12);
  db::SpqrLeastSquares qr;
  DenseMat X;
  EXPECT_THROW(qr.solve(DenseMat::Ones(3, 1), X), db::SolverError);
  const SpMat L = mesh_laplacian(6, 5, true, rng);
  EXPECT_THROW(qr.factorize(SpMat(L.topRows(10))), db::SolverError);  // m < n
  SpMat zero_col = least_squares_matrix(L, {0, 3}, 1.0);
  zero_col.prune([](int, int c, double) { return c != 7; });  // column 7 empty: rank deficient
  EXPECT_THROW(qr.factorize(zero_col), db::SolverError);
  EXPECT_THROW(db::SpqrLeastSquares("bogus"), db::Error);
}

}  // namespace
