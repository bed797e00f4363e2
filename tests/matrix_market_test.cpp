// Matrix Market out and in (systems/matrix_market.h) on the systems of a BS08 edit (methods/edit_system.h):
// written and read back, every index and value is the same bits; the least-squares A gives K within the
// rounding bound of the products; malformed files are refused naming the cause.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

#include "edit/edit_io.h"
#include "methods/edit_system.h"
#include "solvers/base/atomic_file.h"
#include "systems/matrix_market.h"
#include "test_util.h"

namespace db {
namespace {

class MatrixMarket : public TempDirTest {
 protected:
  static EditCase cactus() { return load_edit_case((bs08_dir() / "cactus").string()); }
  static DeformOptions options(Method m, ConstraintMode c) {
    DeformOptions o;
    o.method = m;
    o.constraints = c;
    return o;
  }
};

// Same pattern, same bits (memcmp: -0.0 and 0.0, or NaN payloads, would differ).
void expect_identical(const SpMat& a, const SpMat& b) {
  ASSERT_EQ(a.rows(), b.rows());
  ASSERT_EQ(a.cols(), b.cols());
  ASSERT_EQ(a.nonZeros(), b.nonZeros());
  SpMat x = a, y = b;
  x.makeCompressed();
  y.makeCompressed();
  const auto nnz = std::size_t(x.nonZeros());
  EXPECT_EQ(0, std::memcmp(x.outerIndexPtr(), y.outerIndexPtr(), sizeof(int) * std::size_t(x.cols() + 1)));
  EXPECT_EQ(0, std::memcmp(x.innerIndexPtr(), y.innerIndexPtr(), sizeof(int) * nnz));
  EXPECT_EQ(0, std::memcmp(x.valuePtr(), y.valuePtr(), sizeof(double) * nnz));
}

TEST_F(MatrixMarket, EverySystemOfAnEditRoundTripsExactly) {
  const EditCase ec = cactus();
  for (Method m : {Method::Lap, Method::Tf, Method::Lri})
    for (ConstraintMode c : {ConstraintMode::Hard, ConstraintMode::Soft})
      for (const EditSystem& s : edit_systems(ec.mesh, ec.edit, options(m, c))) {
        SCOPED_TRACE(s.name + (c == ConstraintMode::Hard ? " hard" : " soft"));
        write_atomically(path("K.mtx"), [&](std::ostream& o) { write_market_symmetric(o, s.K, "a comment\nof two lines"); });
        expect_identical(read_market_spd(path("K.mtx")), s.K);
        if (s.rhs.size() == 0) continue;
        write_atomically(path("b.mtx"), [&](std::ostream& o) { write_market_array(o, s.rhs); });
        const DenseMat b = read_market_array(path("b.mtx"), s.K.rows());
        ASSERT_EQ(b.rows(), s.rhs.rows());
        ASSERT_EQ(b.cols(), s.rhs.cols());
        EXPECT_EQ(0, std::memcmp(b.data(), s.rhs.data(), sizeof(double) * std::size_t(b.size())));
      }
}

TEST_F(MatrixMarket, GeneralSymmetricFileReadsAsItsUpperTriangle) {
  write("g.mtx", "%%MatrixMarket matrix coordinate real general\n3 3 5\n1 1 4\n2 1 -1\n1 2 -1\n2 2 4\n3 3 2.5\n");
  write("s.mtx", "%%MatrixMarket matrix coordinate real symmetric\n3 3 4\n1 1 4\n2 1 -1\n2 2 4\n3 3 2.5\n");
  expect_identical(read_market_spd(path("g.mtx")), read_market_spd(path("s.mtx")));
  const SpMat K = read_market_spd(path("s.mtx"));
  EXPECT_EQ(K.coeff(0, 1), -1.0);
  EXPECT_EQ(K.coeff(1, 0), 0.0);  // upper triangle only
}

// A = [A_u; w S]: A^T A is K up to the rounding of two differently ordered sums of the same products, each within
// gamma_k (|A|^T |A|)_ij, k the most entries a column of A holds (Higham, Accuracy and Stability, 3.5).
TEST_F(MatrixMarket, LeastSquaresAGivesTheNormalMatrixWithinRounding) {
  const EditCase ec = cactus();
  for (Method m : {Method::Lap, Method::Tf}) {
    const DeformOptions o = options(m, ConstraintMode::Soft);
    const LeastSquaresSystem ls = edit_least_squares(ec.mesh, ec.edit, o);
    const SpMat K = edit_systems(ec.mesh, ec.edit, o)[0].K;
    const SpMat AtA = SpMat(ls.A.transpose() * ls.A).triangularView<Eigen::Upper>();
    const SpMat absA = ls.A.cwiseAbs();
    const SpMat bound = SpMat(absA.transpose() * absA).triangularView<Eigen::Upper>();
    int k = 0;
    for (int j = 0; j < ls.A.outerSize(); ++j) k = std::max(k, int(ls.A.col(j).nonZeros()));
    const double u = std::numeric_limits<double>::epsilon() / 2, gamma = 2 * k * u / (1 - k * u);
    const SpMat diff = AtA - K;
    ASSERT_EQ(K.rows(), ls.A.cols());
    for (int j = 0; j < diff.outerSize(); ++j)
      for (SpMat::InnerIterator it(diff, j); it; ++it)
        ASSERT_LE(std::abs(it.value()), gamma * bound.coeff(it.row(), it.col()) + 1e-300)
            << to_string(m) << " entry (" << it.row() << ", " << it.col() << ")";
    // A^T b is the right-hand side, within the same bound on |A|^T |b|.
    const DenseMat rhs = edit_systems(ec.mesh, ec.edit, o)[0].rhs, Atb = ls.A.transpose() * ls.b;
    const DenseMat rbound = absA.transpose() * ls.b.cwiseAbs();
    ASSERT_EQ(rhs.rows(), Atb.rows());
    ASSERT_EQ(rhs.cols(), Atb.cols());
    for (Eigen::Index i = 0; i < rhs.size(); ++i)
      ASSERT_LE(std::abs(rhs.data()[i] - Atb.data()[i]), gamma * rbound.data()[i] + 1e-300) << to_string(m) << " rhs " << i;
  }
  EXPECT_THROW(edit_least_squares(ec.mesh, ec.edit, options(Method::Lri, ConstraintMode::Soft)), UsageError);
}

TEST_F(MatrixMarket, MalformedFilesAreRefusedNamingTheCause) {
  const std::string sym = "%%MatrixMarket matrix coordinate real symmetric\n";
  const std::pair<std::string, std::string> cases[] = {
      {"", "empty file"},
      {"hello\n", "not a Matrix Market file"},
      {"%%MatrixMarket matrix array real general\n2 1\n1\n2\n", "must be 'coordinate'"},
      {"%%MatrixMarket matrix coordinate complex symmetric\n1 1 1\n1 1 1 0\n", "only real"},
      {sym + "2 3 2\n1 1 1\n2 2 1\n", "not square"},
      {sym + "100 100 1000\n1 1 1\n", "more than a file of"},
      {sym + "2 2 3\n1 1 1\n2 2 1\n", "2 entries, but the header promises 3"},
      {sym + "2 2 2\n1 1 1\n2 2 1\n2 1 0.5\n", "more entries than"},
      {sym + "2 2 3\n1 1 1\n1 2 0.5\n2 2 1\n", "above the diagonal"},
      {sym + "2 2 2\n1 1 1\n3 3 1\n", "outside [1, 2]"},
      {sym + "2 2 2\n1 1 1\n2 2 nan\n", "not finite"},
      {sym + "2 2 2\n1 1 1\n2 2 x\n", "not a number"},
      {sym + "2 2 3\n1 1 1\n2 2 1\n2 2 1\n", "given twice"},
      {sym + "2 2 2\n1 1 1\n2 1 1\n", "diagonal entry 2 is missing or zero"},
      {sym + "2 2 2\n1 1 -1\n2 2 1\n", "diagonal entry 1 is -1"},
      {"%%MatrixMarket matrix coordinate real general\n2 2 3\n1 1 1\n2 1 1\n2 2 1\n", "not symmetric"},
      {"%%MatrixMarket matrix coordinate real general\n2 2 4\n1 1 1\n2 1 1\n1 2 2\n2 2 1\n", "not symmetric"},
  };
  for (const auto& [text, why] : cases) expect_input_error([&] { read_market_spd(write("m.mtx", text)); }, why);
  expect_input_error([&] { read_market_spd(path("missing.mtx")); }, "missing.mtx");
  const std::string arr = "%%MatrixMarket matrix array real general\n";
  expect_input_error([&] { read_market_array(write("b.mtx", arr + "3 1\n1\n2\n3\n"), 2); }, "3 rows, but the matrix has 2");
  expect_input_error([&] { read_market_array(write("b.mtx", arr + "2 2\n1\n2\n3\n"), 2); }, "3 values, but the header promises 4");
  expect_input_error([&] { read_market_array(write("b.mtx", arr + "2 1\n1 2\n3\n"), 2); }, "one value");
}

}  // namespace
}  // namespace db
