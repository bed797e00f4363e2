// The mumps backend beyond the conformance suite: its pivot statistic against a dense LDL^T in MUMPS's own
// elimination order, every ordering it accepts, the out-of-core factor and its files, MUMPS's errors explained;
// and DistributedMumps and the `mumps` backend on ranks (MumpsOnRanks), whose tests run on however many ranks
// started this binary: one under plain ctest (an MPI singleton, initialized on first use), two in the ctest case
// solvers_mumps_2ranks (scripts/mpirun.sh 2). Under 2 ranks make_solver("mumps") is itself the backend on ranks.
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "solvers/base/error.h"
#include "solvers/linear_solver.h"
#include "solvers/mumps_distributed.h"
#include "solvers/mumps_instance.h"
#include "solvers/mumps_mpi.h"
#include "solvers/tests/exact_reference.h"

namespace {

using db::DenseMat;
using db::SpMat;
namespace fs = std::filesystem;

//! Upper triangle of (grid Laplacian)^2 + shift on an nx x ny grid with varying weights, expanded to 3x3 SPD blocks
//! when `block` is 3: the pattern of the deformation systems (2-ring, interleaved x, y, z).
SpMat grid_system(int nx, int ny, int block, double shift) {
  const int n = nx * ny;
  std::vector<Eigen::Triplet<double>> t;
  auto edge = [&](int a, int b, double w) {
    t.emplace_back(a, b, -w);
    t.emplace_back(b, a, -w);
    t.emplace_back(a, a, w);
    t.emplace_back(b, b, w);
  };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int v = i + nx * j;
      if (i + 1 < nx) edge(v, v + 1, 1.0 + 0.1 * ((i * 7 + j) % 5));
      if (j + 1 < ny) edge(v, v + nx, 1.0 + 0.1 * ((i + j * 3) % 4));
    }
  SpMat L(n, n);
  L.setFromTriplets(t.begin(), t.end());
  SpMat A = SpMat(L.transpose()) * L;
  for (int v = 0; v < n; v += 17) A.coeffRef(v, v) += shift;
  if (block == 3) {
    const Eigen::Matrix3d S = (Eigen::Matrix3d() << 2.0, 0.3, -0.2, 0.3, 1.5, 0.1, -0.2, 0.1, 1.0).finished();
    std::vector<Eigen::Triplet<double>> k;
    for (int j = 0; j < A.outerSize(); ++j)
      for (SpMat::InnerIterator it(A, j); it; ++it)
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) k.emplace_back(3 * int(it.row()) + a, 3 * j + b, it.value() * S(a, b));
    A.resize(3 * n, 3 * n);
    A.setFromTriplets(k.begin(), k.end());
  }
  SpMat U = A.triangularView<Eigen::Upper>();
  U.makeCompressed();
  return U;
}

DenseMat solve_with(const std::string& backend, db::SolverOptions o, const SpMat& U, const DenseMat& B,
                    db::FactorStats* stats = nullptr) {
  auto s = db::make_solver(backend, o);
  s->analyze(U);
  s->factorize(U);
  DenseMat X;
  s->solve(B, X);
  if (stats) *stats = s->stats();
  return X;
}

using db::exact::pivot_ratio_error;
using db::exact::rel;

// The smallest pivot ratio is MUMPS's record of the smallest |pivot| of the diagonally scaled matrix (an
// undocumented DKEEP entry): it must be the smallest L_kk^2 / A_kk of a dense Cholesky in the order MUMPS
// eliminated (SYM_PERM), for a given order and for one MUMPS computes.
TEST(Mumps, MinPivotRatioIsTheDenseOneInMumpsOrder) {
  const SpMat U = grid_system(9, 8, 1, 0.5);
  const DenseMat A = DenseMat(SpMat(U.selfadjointView<Eigen::Upper>()));
  const int n = int(U.cols());
  std::vector<MUMPS_INT> irn, jcn;
  for (int j = 0; j < n; ++j)
    for (SpMat::InnerIterator it(U, j); it; ++it) {
      irn.push_back(MUMPS_INT(it.row()) + 1);
      jcn.push_back(j + 1);
    }
  for (const std::string ordering : {"natural", "amd", "pord"}) {
    SCOPED_TRACE(ordering);
    db::SolverOptions o;
    o.ordering = ordering;
    db::mumps::Instance m(MPI_COMM_SELF, o, "test");
    m.id().n = n;
    m.id().nnz = MUMPS_INT8(irn.size());
    m.id().irn = irn.data();
    m.id().jcn = jcn.data();
    std::vector<int> identity(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) identity[std::size_t(i)] = i + 1;
    m.analyze(&identity);
    const db::DenseVec d = A.diagonal();
    m.set_diagonal(std::vector<double>(d.data(), d.data() + n));
    m.id().a = const_cast<double*>(U.valuePtr());
    m.factorize(true);
    std::vector<int> order(static_cast<std::size_t>(n));  // order[k]: the unknown eliminated k-th
    for (int i = 0; i < n; ++i) order[std::size_t(m.id().sym_perm[i] - 1)] = i;
    DenseMat P(n, n);
    for (int k = 0; k < n; ++k)
      for (int l = 0; l < n; ++l) P(k, l) = A(order[std::size_t(k)], order[std::size_t(l)]);
    const DenseMat L = P.llt().matrixL();
    double ref = 1e300;
    for (int k = 0; k < n; ++k) ref = std::min(ref, L(k, k) * L(k, k) / P(k, k));
    EXPECT_NEAR(m.report().min_pivot_ratio, ref, 2 * pivot_ratio_error(std::size_t(n)));  // both computed
    EXPECT_EQ(m.ordering_used(), ordering);
  }
}

// Every ordering the backend lists solves the scalar and the 3x3-block system exactly up to the rounding the
// system's conditioning allows (solvers/tests/exact_reference.h; so does CHOLMOD), and names itself:
// MUMPS's own orderings on the compressed block graph ("-block3"), this project's METIS given to MUMPS.
TEST(Mumps, EveryOrderingAgreesWithCholmod) {
  for (int block : {1, 3}) {
    const SpMat U = grid_system(14, 11, block, 0.5);
    const DenseMat B = DenseMat::Random(U.rows(), 3);
    db::SolverOptions o;
    o.block_size = block;
    const DenseMat Xref = db::exact::exact_solution(U, B, block);
    const double tol = db::exact::solve_bound(db::exact::condition_number(U));
    EXPECT_WITHIN(rel(solve_with("cholmod_supernodal", o, U, B), Xref), tol);
    for (const std::string& ordering : db::solver_info("mumps").orderings) {
      SCOPED_TRACE(fmt::format("{} block {}", ordering, block));
      o.ordering = ordering;
      db::FactorStats st;
      EXPECT_WITHIN(rel(solve_with("mumps", o, U, B, &st), Xref), tol);
      const std::string suffix = block == 3 && ordering != "natural" ? "-block3" : "";
      if (ordering == "default") {
        EXPECT_NE(st.ordering_used.find(suffix), std::string::npos) << st.ordering_used;
      } else if (ordering == "ptscotch") {  // one process: SCOTCH's sequential ordering
        EXPECT_EQ(st.ordering_used, "scotch" + suffix);
      } else {
        EXPECT_EQ(st.ordering_used, ordering + suffix);
      }
      EXPECT_GT(st.flops, double(st.nnz_factor));
      EXPECT_GE(st.factor_bytes, st.nnz_factor * sizeof(double));
    }
  }
}

std::vector<fs::path> mumps_files(const fs::path& dir) {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().rfind("deformbench-mumps", 0) == 0) out.push_back(e.path());
  return out;
}

// Out of core: the exact solution up to the rounding the system's conditioning allows, as in memory (each is held
// to it: the two solves round differently), the factor in MUMPS's files in the directory while the solver lives
// (about the factor's size), none left after; a directory that does not exist is named at once.
TEST(Mumps, OutOfCoreFactorLivesInItsDirectory) {
  const SpMat U = grid_system(40, 36, 3, 0.5);
  const DenseMat B = DenseMat::Random(U.rows(), 2);
  const fs::path dir = fs::temp_directory_path() / fmt::format("deformbench-mumps-test-{}", ::getpid());
  fs::create_directories(dir);
  db::SolverOptions o;
  o.block_size = 3;
  db::FactorStats in_core;
  const DenseMat Xref = db::exact::exact_solution(U, B, 3);
  const double tol = db::exact::solve_bound(db::exact::condition_number(U));
  EXPECT_WITHIN(rel(solve_with("mumps", o, U, B, &in_core), Xref), tol) << "in memory";
  o.factor_dir = dir.string();
  {
    auto s = db::make_solver("mumps", o);
    s->factorize(U);
    DenseMat X;
    s->solve(B, X);
    EXPECT_WITHIN(rel(X, Xref), tol) << "out of core";
    const db::FactorStats st = s->stats();
    EXPECT_TRUE(st.factor_on_disk);
    EXPECT_EQ(st.nnz_factor, in_core.nnz_factor);
    std::uintmax_t bytes = 0;
    for (const fs::path& f : mumps_files(dir)) bytes += fs::file_size(f);
    EXPECT_GE(double(bytes), 0.9 * double(st.nnz_factor) * sizeof(double)) << bytes;
  }
  EXPECT_TRUE(mumps_files(dir).empty()) << "MUMPS removes its files at the end";
  fs::remove_all(dir);
  o.factor_dir = (dir / "missing").string();
  try {
    db::make_solver("mumps", o)->factorize(U);
    FAIL() << "expected an error for a missing directory";
  } catch (const db::Error& e) {
    EXPECT_NE(std::string(e.what()).find("missing"), std::string::npos) << e.what();
  }
}

// MPI runs at MPI_THREAD_MULTIPLE (solvers/mumps_mpi.h): PT-Scotch's parallel ordering calls MPI from several threads
// at once, and under the SERIALIZED level it crashed now and then in DistributedMumps' ptscotch cases.
TEST(Mumps, MpiRunsAtThreadMultiple) { EXPECT_TRUE(db::mpi::threads_multiple()); }

// Failures say what MUMPS found: negative pivots (indefinite), a pivot at rounding level (singular), and MUMPS's
// own error codes in words.
TEST(Mumps, FailuresAreExplained) {
  SpMat U = grid_system(10, 9, 1, 0.5);
  SpMat bad = U;
  bad.coeffRef(20, 20) = -bad.coeffRef(20, 20);
  try {
    db::make_solver("mumps")->factorize(bad);
    FAIL() << "expected SolverError";
  } catch (const db::SolverError& e) {
    EXPECT_NE(std::string(e.what()).find("not positive definite (1 of 90 pivots negative)"), std::string::npos)
        << e.what();
  }
  const SpMat singular = grid_system(10, 9, 1, 0.0);  // no shift: constants are in the null space
  try {
    db::make_solver("mumps")->factorize(singular);
    FAIL() << "expected SolverError";
  } catch (const db::SolverError& e) {
    // The last pivot is zero up to rounding, whose sign the BLAS kernels decide: either message names the cause.
    const std::string what = e.what();
    EXPECT_TRUE(what.find("numerically singular") != std::string::npos ||
                what.find("not positive definite (1 of 90 pivots negative)") != std::string::npos)
        << what;
  }
  EXPECT_NE(db::mumps::error_text(-9, 0).find("ICNTL(14)"), std::string::npos);
  EXPECT_NE(db::mumps::error_text(-13, -5).find("5000000 entries"), std::string::npos);
  EXPECT_NE(db::mumps::error_text(-999, 3).find("users' guide"), std::string::npos);
}

//! This rank's share of U's entries: the columns [r n / size, (r + 1) n / size), and, with two ranks or more, half
//! of every diagonal entry on each of the first and the last rank (MUMPS sums an entry given twice).
struct Share {
  std::vector<int> rows, cols;
  std::vector<double> values;
};
Share share_of(const SpMat& U) {
  const int n = int(U.cols()), r = db::mpi::rank(), p = db::mpi::size();
  Share s;
  for (int j = 0; j < n; ++j)
    for (SpMat::InnerIterator it(U, j); it; ++it) {
      const bool mine = j >= int(std::int64_t(r) * n / p) && j < int(std::int64_t(r + 1) * n / p);
      const bool diagonal = it.row() == j;
      const bool split = p > 1 && diagonal && (r == 0 || r == p - 1);
      if (!mine && !split) continue;
      s.rows.push_back(int(it.row()));
      s.cols.push_back(j);
      s.values.push_back(split ? 0.5 * it.value() : it.value());
    }
  return s;
}

// Distributed input on every rank gives the exact solution on rank 0 (up to the rounding the system's conditioning
// allows, as CHOLMOD's), for MUMPS's own orderings and a given one,
// scalar and 3x3-block systems; the statistics are global.
TEST(DistributedMumps, MatchesOneProcess) {
  for (int block : {1, 3}) {
    const SpMat U = grid_system(23, 19, block, 0.5);
    const DenseMat B = DenseMat::Random(U.rows(), 3);  // the same on every rank (Eigen's fixed seed)
    db::SolverOptions o;
    o.block_size = block;
    const DenseMat Xref = db::exact::exact_solution(U, B, block);
    const double tol = db::exact::solve_bound(db::exact::condition_number(U));
    EXPECT_WITHIN(rel(solve_with("cholmod_supernodal", o, U, B), Xref), tol);
    const DenseMat A = DenseMat(SpMat(U.selfadjointView<Eigen::Upper>()));
    const db::DenseVec d = A.diagonal().cwiseSqrt().cwiseInverse();
    const Eigen::SelfAdjointEigenSolver<DenseMat> eig(d.asDiagonal() * A * d.asDiagonal(), Eigen::EigenvaluesOnly);
    const Eigen::VectorXd& ev = eig.eigenvalues();
    const std::size_t n = std::size_t(U.rows());
    for (const std::string& ordering : db::solver_info("mumps").orderings) {
      if (ordering == "metis") continue;
      SCOPED_TRACE(fmt::format("{} block {} on {} ranks", ordering, block, db::mpi::size()));
      o.ordering = ordering;
      db::DistributedMumps m(o);
      Share s = share_of(U);
      m.analyze(U.rows(), s.rows, s.cols);
      m.factorize(s.values);
      DenseMat X = db::mpi::rank() == 0 ? B : DenseMat();
      m.solve(X);
      if (db::mpi::rank() == 0) {
        EXPECT_WITHIN(rel(X, Xref), tol);
      }
      const db::FactorStats st = m.stats();
      EXPECT_EQ(st.n, std::size_t(U.rows()));
      EXPECT_EQ(st.nnz_matrix, std::size_t(U.nonZeros()) + (db::mpi::size() > 1 ? std::size_t(U.rows()) : 0));
      db::FactorStats one;  // given the order, the same pivots as on one process (an ordering MUMPS computes
      solve_with("mumps", o, U, B, &one);  // may break ties by the order the entries arrive in)
      if (ordering == "natural") {
        EXPECT_NEAR(st.min_pivot_ratio, one.min_pivot_ratio, 2 * pivot_ratio_error(n));  // both computed
      }
      // Every pivot of the scaled matrix lies in [its smallest eigenvalue, 1], less the pivot's rounding and the
      // eigenvalue's (backward stable: within n eps ||S|| of S's).
      EXPECT_GE(st.min_pivot_ratio, ev(0) - pivot_ratio_error(n) * (1 + ev(ev.size() - 1)));
      EXPECT_LE(st.min_pivot_ratio, 1.0);
      if (ordering != "ptscotch") {  // parallel analysis on two ranks or more, SCOTCH's on one
        EXPECT_EQ(st.ordering_used, one.ordering_used);
      }
      EXPECT_GT(st.flops, double(st.nnz_factor));
      EXPECT_EQ(m.report().processes, db::mpi::size());
      if (db::mpi::rank() == 0) {
        EXPECT_EQ(m.report().mb_in_core_rank.size(), std::size_t(db::mpi::size()));
      }
    }
  }
}

// A failure on any rank is a failure on every rank (none is left waiting): a NaN on the last rank, an entry below the
// diagonal on the first, an indefinite matrix, a right-hand side of the wrong size on rank 0; and metis is refused.
TEST(DistributedMumps, EveryRankFailsTogether) {
  const SpMat U = grid_system(12, 10, 1, 0.5);
  const int last = db::mpi::size() - 1;
  {
    db::DistributedMumps m({});
    Share s = share_of(U);
    m.analyze(U.rows(), s.rows, s.cols);
    if (db::mpi::rank() == last) s.values[0] = std::nan("");
    EXPECT_THROW(m.factorize(s.values), db::SolverError);
  }
  {
    db::DistributedMumps m({});
    Share s = share_of(U);
    if (db::mpi::rank() == 0) {  // an entry below the diagonal
      s.rows.push_back(1);
      s.cols.push_back(0);
    }
    EXPECT_THROW(m.analyze(U.rows(), s.rows, s.cols), db::Error);
  }
  {
    SpMat bad = U;
    bad.coeffRef(40, 40) = -bad.coeffRef(40, 40);
    db::DistributedMumps m({});
    Share s = share_of(bad);
    m.analyze(bad.rows(), s.rows, s.cols);
    try {
      m.factorize(s.values);
      ADD_FAILURE() << "expected SolverError";
    } catch (const db::SolverError& e) {
      EXPECT_NE(std::string(e.what()).find("not positive definite"), std::string::npos) << e.what();
    }
    DenseMat X = DenseMat::Ones(U.rows(), 1);
    EXPECT_THROW(m.solve(X), db::SolverError) << "no factor after a failure";
  }
  {
    db::DistributedMumps m({});
    Share s = share_of(U);
    m.analyze(U.rows(), s.rows, s.cols);
    m.factorize(s.values);
    DenseMat X = db::mpi::rank() == 0 ? DenseMat::Ones(U.rows() + 1, 1) : DenseMat();
    EXPECT_THROW(m.solve(X), db::SolverError);
  }
  db::SolverOptions metis;
  metis.ordering = "metis";
  EXPECT_THROW(db::DistributedMumps{metis}, db::Error);
}

// Out of core on every rank: as in memory, the exact solution up to the rounding the system's conditioning allows
// (each is held to it: the two round differently).
TEST(DistributedMumps, OutOfCore) {
  const SpMat U = grid_system(30, 27, 3, 0.5);
  const DenseMat B = DenseMat::Random(U.rows(), 2);
  db::SolverOptions o;
  o.block_size = 3;
  DenseMat X[2];
  for (int k = 0; k < 2; ++k) {
    if (k == 1) o.factor_dir = fs::temp_directory_path().string();
    db::DistributedMumps m(o);
    Share s = share_of(U);
    m.analyze(U.rows(), s.rows, s.cols);
    m.factorize(s.values);
    EXPECT_EQ(m.stats().factor_on_disk, k == 1);
    X[k] = db::mpi::rank() == 0 ? B : DenseMat();
    m.solve(X[k]);
  }
  const DenseMat Xref = db::exact::exact_solution(U, B, 3);
  const double tol = db::exact::solve_bound(db::exact::condition_number(U));
  if (db::mpi::rank() == 0) {
    EXPECT_WITHIN(rel(X[0], Xref), tol) << "in memory";
    EXPECT_WITHIN(rel(X[1], Xref), tol) << "out of core";
  }
}

// The `mumps` backend of the registry on every rank at once (on one rank: one process): each rank passes the same
// system, every rank gets the solution, the exact one up to the rounding the system's conditioning allows (as
// CHOLMOD's), for a given order and one MUMPS computes, again after
// a refactorization that consumes the matrix; a solve before any factorization fails on every rank.
TEST(MumpsOnRanks, EveryRankGetsTheSolution) {
  const SpMat U = grid_system(23, 19, 3, 0.5);
  const DenseMat B = DenseMat::Random(U.rows(), 2);  // the same on every rank (Eigen's fixed seed)
  db::SolverOptions o;
  o.block_size = 3;
  const DenseMat Xref = db::exact::exact_solution(U, B, 3);
  const double tol = db::exact::solve_bound(db::exact::condition_number(U));
  EXPECT_WITHIN(rel(solve_with("cholmod_supernodal", o, U, B), Xref), tol);
  for (const std::string ordering : {"natural", "default"}) {
    SCOPED_TRACE(fmt::format("{} on {} ranks", ordering, db::mpi::size()));
    o.ordering = ordering;
    auto s = db::make_solver("mumps", o);
    EXPECT_EQ(s->name(), "mumps");
    DenseMat X;
    EXPECT_THROW(s->solve(B, X), db::SolverError);
    s->analyze(U);
    for (int round = 0; round < 2; ++round) {  // the second consumes its matrix
      SpMat consumed = U;
      if (round == 0) s->factorize(U);
      else s->factorize_consuming(consumed);
      EXPECT_EQ(consumed.nonZeros(), round == 0 ? U.nonZeros() : 0);
      s->solve(B, X);
      EXPECT_WITHIN(rel(X, Xref), tol) << "round " << round;
    }
    const db::FactorStats st = s->stats();
    EXPECT_EQ(st.n, std::size_t(U.rows()));
    EXPECT_GT(st.nnz_factor, std::size_t(U.rows()));
    EXPECT_GT(st.min_pivot_ratio, 0);
  }
}

// On several ranks, ranks that pass different matrices (here: the last passes the transposed grid's, the same size)
// are refused together.
// Only under 2 ranks (ctest solvers_mumps_2ranks): the suite's name keeps it out of the one-process discovery.
TEST(MumpsTwoRanksOnly, DifferentMatricesAreRefused) {
  ASSERT_GE(db::mpi::size(), 2);
  const bool last = db::mpi::rank() == db::mpi::size() - 1;
  const SpMat U = last ? grid_system(19, 23, 1, 0.5) : grid_system(23, 19, 1, 0.5);
  auto s = db::make_solver("mumps", {});
  try {
    s->analyze(U);
    ADD_FAILURE() << "expected SolverError";
  } catch (const db::SolverError& e) {
    EXPECT_NE(std::string(e.what()).find("different matrices"), std::string::npos) << e.what();
  }
}

}  // namespace
