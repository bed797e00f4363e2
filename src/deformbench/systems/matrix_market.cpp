#include "systems/matrix_market.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "core/input_file.h"
#include "solvers/base/error.h"

namespace db {
namespace {

constexpr std::size_t kMaxLine = 1024;
constexpr long long kMaxDim = std::numeric_limits<int>::max();
constexpr int kMinEntryBytes = 6;  // "1 1 1\n": the shortest coordinate line
constexpr int kMinValueBytes = 2;  // "1\n": the shortest array line

void header(std::ostream& out, const char* kind, const std::string& comment) {
  fmt::print(out, "%%MatrixMarket matrix {}\n", kind);
  std::istringstream lines(comment);
  for (std::string line; std::getline(lines, line);) fmt::print(out, "% {}\n", line);
}

void entries(std::ostream& out, const SpMat& M) {
  for (int j = 0; j < M.outerSize(); ++j)
    for (SpMat::InnerIterator it(M, j); it; ++it) fmt::print(out, "{} {} {:.17g}\n", it.row() + 1, it.col() + 1, it.value());
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

// The banner's fields: object, format, field, symmetry.
struct Banner {
  std::string format, field, symmetry;
};

// A coordinate or array file read line by line: the banner, then comments, the size line, the data lines.
class Reader {
 public:
  Reader(const std::string& path, const char* what) : path_(path), file_(path, what) {}

  [[noreturn]] void fail(int line, const std::string& why) const {
    throw InputError(fmt::format("Matrix Market file {}:{}: {}", path_, line, why));
  }
  std::uint64_t size() const { return file_.size(); }

  //! Calls on_banner once, on_size once with the size line's numbers, on_data for each data line's fields.
  void read(const std::function<void(int, const Banner&)>& on_banner,
            const std::function<void(int, const std::vector<std::string>&)>& on_size,
            const std::function<void(int, const std::vector<std::string>&)>& on_data) {
    bool banner = false, sized = false;
    file_.each_line(kMaxLine, [&](int ln, const std::string& line) {
      if (!banner) {
        std::istringstream in(line);
        std::string mm, object;
        Banner b;
        in >> mm >> object >> b.format >> b.field >> b.symmetry;
        if (mm != "%%MatrixMarket" || lower(object) != "matrix")
          fail(ln, "not a Matrix Market file (the first line must be '%%MatrixMarket matrix ...')");
        b = {lower(b.format), lower(b.field), lower(b.symmetry)};
        on_banner(ln, b);
        banner = true;
        return;
      }
      if (line.empty() || line[0] == '%') return;
      std::istringstream in(line);
      std::vector<std::string> f;
      for (std::string w; in >> w;) f.push_back(w);
      if (f.empty()) return;
      if (!sized) {
        on_size(ln, f);
        sized = true;
      } else {
        on_data(ln, f);
      }
      last_ = ln;
    });
    if (!banner) fail(1, "empty file");
    if (!sized) fail(last_, "no size line");
  }
  int last_line() const { return last_; }

  long long integer(int ln, const std::string& s, long long lo, long long hi, const char* what) const {
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(s.c_str(), &end, 10);
    if (errno != 0 || end == s.c_str() || *end != '\0') fail(ln, fmt::format("{} '{}' is not an integer", what, s));
    if (v < lo || v > hi) fail(ln, fmt::format("{} {} is outside [{}, {}]", what, v, lo, hi));
    return v;
  }
  double real(int ln, const std::string& s) const {
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (end == s.c_str() || *end != '\0') fail(ln, fmt::format("value '{}' is not a number", s));
    if (!std::isfinite(v)) fail(ln, fmt::format("value '{}' is not finite", s));
    return v;
  }

 private:
  std::string path_;
  InputFile file_;
  int last_ = 1;
};

void check_real(const Reader& r, int ln, const Banner& b) {
  if (b.field != "real" && b.field != "integer")
    r.fail(ln, fmt::format("field '{}': only real (or integer) values are read", b.field));
}

}  // namespace

void write_market_symmetric(std::ostream& out, const SpMat& upper, const std::string& comment) {
  if (upper.rows() != upper.cols()) throw Error("write_market_symmetric: the matrix is not square");
  const SpMat L = upper.transpose();  // the lower triangle, column by column
  for (int j = 0; j < L.outerSize(); ++j)
    for (SpMat::InnerIterator it(L, j); it; ++it)
      if (it.row() < it.col()) throw Error("write_market_symmetric: the matrix is not an upper triangle");
  header(out, "coordinate real symmetric", comment);
  fmt::print(out, "{} {} {}\n", L.rows(), L.cols(), L.nonZeros());
  entries(out, L);
}

void write_market_general(std::ostream& out, const SpMat& A, const std::string& comment) {
  header(out, "coordinate real general", comment);
  fmt::print(out, "{} {} {}\n", A.rows(), A.cols(), A.nonZeros());
  entries(out, A);
}

void write_market_array(std::ostream& out, const DenseMat& B, const std::string& comment) {
  header(out, "array real general", comment);
  fmt::print(out, "{} {}\n", B.rows(), B.cols());
  for (Eigen::Index j = 0; j < B.cols(); ++j)
    for (Eigen::Index i = 0; i < B.rows(); ++i) fmt::print(out, "{:.17g}\n", B(i, j));
}

SpMat read_market_spd(const std::string& path) {
  Reader r(path, "matrix");
  bool symmetric = false;
  long long n = 0, nnz = 0, count = 0;
  std::vector<Eigen::Triplet<double, int>> t;
  r.read(
      [&](int ln, const Banner& b) {
        if (b.format != "coordinate") r.fail(ln, fmt::format("format '{}': a system matrix must be 'coordinate'", b.format));
        check_real(r, ln, b);
        if (b.symmetry != "symmetric" && b.symmetry != "general")
          r.fail(ln, fmt::format("symmetry '{}': only symmetric or general matrices are read", b.symmetry));
        symmetric = b.symmetry == "symmetric";
      },
      [&](int ln, const std::vector<std::string>& f) {
        if (f.size() != 3) r.fail(ln, "the size line must be 'ROWS COLUMNS ENTRIES'");
        const long long rows = r.integer(ln, f[0], 1, kMaxDim, "rows");
        n = r.integer(ln, f[1], 1, kMaxDim, "columns");
        if (rows != n) r.fail(ln, fmt::format("the matrix is {} x {}, not square: not a system matrix", rows, n));
        const double most = symmetric ? 0.5 * double(n) * double(n + 1) : double(n) * double(n);
        nnz = r.integer(ln, f[2], n, static_cast<long long>(std::min(most, 9e18)), "entries");
        if (double(nnz) * kMinEntryBytes > double(r.size()))
          r.fail(ln, fmt::format("the header promises {} entries, more than a file of {} bytes can hold", nnz, r.size()));
        t.reserve(static_cast<std::size_t>(nnz));
      },
      [&](int ln, const std::vector<std::string>& f) {
        if (f.size() != 3) r.fail(ln, "an entry must be 'ROW COLUMN VALUE'");
        if (++count > nnz) r.fail(ln, fmt::format("more entries than the {} the header promises", nnz));
        const long long i = r.integer(ln, f[0], 1, n, "row") - 1, j = r.integer(ln, f[1], 1, n, "column") - 1;
        if (symmetric && i < j)
          r.fail(ln, fmt::format("entry ({}, {}) is above the diagonal: a symmetric file holds the lower triangle",
                                 i + 1, j + 1));
        const double v = r.real(ln, f[2]);
        if (symmetric) t.emplace_back(int(j), int(i), v);  // the transpose: the upper triangle
        else t.emplace_back(int(i), int(j), v);
      });
  if (count != nnz) r.fail(r.last_line(), fmt::format("{} entries, but the header promises {}", count, nnz));
  SpMat A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  if (A.nonZeros() != nnz) r.fail(r.last_line(), "an entry is given twice");
  if (!symmetric) {
    const SpMat At = A.transpose();
    for (int j = 0; j < A.outerSize(); ++j) {
      SpMat::InnerIterator a(A, j), b(At, j);
      for (; a && b; ++a, ++b)
        if (a.row() != b.row() || a.value() != b.value())
          r.fail(r.last_line(), fmt::format("the matrix is not symmetric (column {} differs from row {}): the study "
                                            "takes symmetric positive-definite systems",
                                            j + 1, j + 1));
      if (a || b) r.fail(r.last_line(), fmt::format("the matrix is not symmetric (the pattern of column {} differs from "
                                                    "row {}): the study takes symmetric positive-definite systems",
                                                    j + 1, j + 1));
    }
    A = SpMat(A.triangularView<Eigen::Upper>());
  }
  for (int j = 0; j < A.outerSize(); ++j) {
    double d = 0;
    for (SpMat::InnerIterator it(A, j); it; ++it)
      if (it.row() == j) d = it.value();
    if (!(d > 0))
      r.fail(r.last_line(), fmt::format("diagonal entry {} is {}: a symmetric positive-definite matrix has a positive "
                                        "diagonal",
                                        j + 1, d == 0 ? "missing or zero" : fmt::format("{:g}", d)));
  }
  return A;
}

DenseMat read_market_array(const std::string& path, long long rows) {
  Reader r(path, "right-hand side");
  DenseMat B;
  long long count = 0;
  r.read(
      [&](int ln, const Banner& b) {
        if (b.format != "array") r.fail(ln, fmt::format("format '{}': right-hand sides must be 'array'", b.format));
        check_real(r, ln, b);
        if (b.symmetry != "general") r.fail(ln, fmt::format("symmetry '{}': right-hand sides are 'general'", b.symmetry));
      },
      [&](int ln, const std::vector<std::string>& f) {
        if (f.size() != 2) r.fail(ln, "the size line must be 'ROWS COLUMNS'");
        const long long m = r.integer(ln, f[0], 1, kMaxDim, "rows"), c = r.integer(ln, f[1], 1, 4096, "columns");
        if (rows >= 0 && m != rows) r.fail(ln, fmt::format("{} rows, but the matrix has {}", m, rows));
        if (double(m) * double(c) * kMinValueBytes > double(r.size()))
          r.fail(ln, fmt::format("the header promises {} values, more than a file of {} bytes can hold", m * c, r.size()));
        B.resize(m, c);
      },
      [&](int ln, const std::vector<std::string>& f) {
        if (f.size() != 1) r.fail(ln, "an array line holds one value");
        if (count >= B.size()) r.fail(ln, fmt::format("more values than the {} the header promises", B.size()));
        B(count % B.rows(), count / B.rows()) = r.real(ln, f[0]);
        ++count;
      });
  if (count != B.size()) r.fail(r.last_line(), fmt::format("{} values, but the header promises {}", count, B.size()));
  return B;
}

}  // namespace db
