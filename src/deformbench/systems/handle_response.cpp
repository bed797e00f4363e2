#include "systems/handle_response.h"

#include <algorithm>
#include <cmath>

#include "solvers/base/error.h"
#include "solvers/base/resources.h"
#include "core/timer.h"

namespace db {

void HandleResponse::precompute(const MinQuadWithFixed& mq, const DenseMat& xh0, const DenseMat& soft0,
                                const DenseMat& xh_basis, const DenseMat& soft_basis, const std::vector<int>& source) {
  Timer t;
  // The responses' matrices are tens of MB that are written once: huge pages spare most of their first-touch
  // faults (advise_huge_pages), which on a virtual machine cost more than the writes.
  const Eigen::Index n = mq.num_unknown_rows();
  DenseMat rest_rhs, basis_rhs(n, std::max(xh_basis.cols(), soft_basis.cols()));
  advise_huge_pages(basis_rhs.data(), static_cast<std::size_t>(basis_rhs.size()) * sizeof(double));
  mq.rhs_of(xh0, soft0, /*constant=*/true, rest_rhs);
  mq.rhs_of(xh_basis, soft_basis, /*constant=*/false, basis_rhs);  // same shape: into the advised memory
  cols_ = static_cast<int>(rest_rhs.cols());
  m_ = static_cast<int>(basis_rhs.cols());
  DenseMat B(n, cols_ + m_), X;
  advise_huge_pages(B.data(), static_cast<std::size_t>(B.size()) * sizeof(double));
  B << rest_rhs, basis_rhs;
  rest_rhs.resize(0, 0);
  basis_rhs.resize(0, 0);
  mq.solve_columns(B, X);  // the rest pose and every response in one pass over the factor
  if (!X.allFinite()) throw SolverError("handle response: the solve produced non-finite values");

  rows_ = static_cast<int>(source.size());
  const int stride = cols_ + m_;
  std::vector<double>().swap(data_);
  data_.reserve(static_cast<std::size_t>(rows_) * static_cast<std::size_t>(stride));  // allocated, not touched
  advise_huge_pages(data_.data(), data_.capacity() * sizeof(double));
  data_.resize(data_.capacity());
  for (int i = 0; i < rows_; ++i) {
    double* row = &data_[static_cast<std::size_t>(i) * static_cast<std::size_t>(stride)];
    const int r = source[static_cast<std::size_t>(i)];
    for (int c = 0; c < cols_; ++c) row[c] = r >= 0 ? X(r, c) : xh0(hard_row(r), c);
    for (int k = 0; k < m_; ++k) row[cols_ + k] = r >= 0 ? X(r, cols_ + k) : xh_basis(hard_row(r), k);
  }
  seconds_ = t.seconds();
}

void HandleResponse::scale_and_shift(double scale, const Vec3& shift) {
  const int stride = cols_ + m_;
  for (int i = 0; i < rows_; ++i) {
    double* row = &data_[static_cast<std::size_t>(i) * static_cast<std::size_t>(stride)];
    for (int c = 0; c < cols_; ++c) row[c] = row[c] * scale + shift(cols_ == 3 ? c : i % 3);
    for (int k = 0; k < m_; ++k) row[cols_ + k] *= scale;
  }
}

namespace {

// One block of rows; COLS and M fixed at compile time for the shapes the deformers use, so the inner products
// stay in registers and the rows stream.
template <int COLS, int M>
bool evaluate_rows(const double* data, const double* theta, int begin, int end, double* out) {
  constexpr int stride = COLS + M;
  bool finite = true;
  for (int i = begin; i < end; ++i) {
    const double* row = data + static_cast<std::size_t>(i) * stride;
    for (int c = 0; c < COLS; ++c) {
      double y = row[c];
      for (int k = 0; k < M; ++k) y += row[COLS + k] * theta[c * M + k];
      out[static_cast<std::size_t>(i) * COLS + c] = y;
      finite = finite && std::isfinite(y);
    }
  }
  return finite;
}

// Any shape (per-vertex drags: m = 3h or h): Eigen's dot keeps several partial sums, so a long row streams
// instead of waiting on one chain of additions.
bool evaluate_rows_any(int cols, int m, const double* data, const double* theta, int begin, int end, double* out) {
  const int stride = cols + m;
  bool finite = true;
  for (int i = begin; i < end; ++i) {
    const double* row = data + static_cast<std::size_t>(i) * static_cast<std::size_t>(stride);
    const Eigen::Map<const Eigen::VectorXd> r(row + cols, m);
    for (int c = 0; c < cols; ++c) {
      const double y = row[c] + r.dot(Eigen::Map<const Eigen::VectorXd>(theta + static_cast<std::size_t>(c) * m, m));
      out[static_cast<std::size_t>(i) * static_cast<std::size_t>(cols) + c] = y;
      finite = finite && std::isfinite(y);
    }
  }
  return finite;
}

}  // namespace

bool HandleResponse::evaluate(const DenseMat& theta, double* out) const {
  if (theta.rows() != m_ || theta.cols() != cols_) throw Error("HandleResponse::evaluate: theta has the wrong shape");
  std::vector<double> th(static_cast<std::size_t>(m_) * static_cast<std::size_t>(cols_));  // column c contiguous
  for (int c = 0; c < cols_; ++c)
    for (int k = 0; k < m_; ++k) th[static_cast<std::size_t>(c * m_ + k)] = theta(k, c);
  const double* d = data_.data();
  auto block = [&](int begin, int end) {
    if (cols_ == 3 && m_ == 4) return evaluate_rows<3, 4>(d, th.data(), begin, end, out);
    if (cols_ == 1 && m_ == 12) return evaluate_rows<1, 12>(d, th.data(), begin, end, out);
    if (cols_ == 3 && m_ == 3) return evaluate_rows<3, 3>(d, th.data(), begin, end, out);
    return evaluate_rows_any(cols_, m_, d, th.data(), begin, end, out);
  };
  // A thread's start (tens of microseconds on a loaded box) costs more than streaming its share below ~2 MB.
  const int threads = std::clamp(static_cast<int>(bytes() >> 21), 1, std::max(1, worker_threads()));
  if (threads == 1) return block(0, rows_);
  std::vector<char> ok(static_cast<std::size_t>(threads), 1);
  run_tasks(threads, [&](int t) {
    const long long per = (static_cast<long long>(rows_) + threads - 1) / threads;
    const int begin = static_cast<int>(std::min<long long>(rows_, per * t));
    const int end = static_cast<int>(std::min<long long>(rows_, per * (t + 1)));
    ok[static_cast<std::size_t>(t)] = block(begin, end) ? 1 : 0;
  });
  return std::all_of(ok.begin(), ok.end(), [](char c) { return c != 0; });
}

}  // namespace db
