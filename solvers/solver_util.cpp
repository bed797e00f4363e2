#include "solvers/solver_util.h"

#include <dlfcn.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "solvers/base/resources.h"

namespace db::solver_util {

OpenMpSerial::OpenMpSerial() {
  void* self = ::dlopen(nullptr, RTLD_LAZY);
  set_ = reinterpret_cast<void (*)(int)>(::dlsym(self, "omp_set_max_active_levels"));
  auto get = reinterpret_cast<int (*)()>(::dlsym(self, "omp_get_max_active_levels"));
  if (!set_ || !get) {
    set_ = nullptr;
    return;
  }
  saved_ = get();
  set_(0);
}

OpenMpSerial::~OpenMpSerial() {
  if (set_) set_(saved_);
}

void check_options(const SolverOptions& options, const std::string& who) {
  const std::vector<std::string> valid = solver_info(who).orderings;
  if (std::find(valid.begin(), valid.end(), options.ordering) == valid.end())
    throw Error(fmt::format("{}: unknown ordering '{}' (valid: {})", who, options.ordering, fmt::join(valid, ", ")));
  if (options.block_size < 1) throw Error(fmt::format("{}: block_size must be >= 1", who));
}

void check_square(const SpMat& upper, const std::string& who) {
  if (upper.rows() != upper.cols())
    throw SolverError(fmt::format("{}: matrix is {} x {}, expected square", who, upper.rows(), upper.cols()));
}

void check_finite_values(const SpMat& upper, const std::string& who) {
  // Column ranges on the worker threads find the first column holding a non-finite entry, whatever the threads.
  std::atomic<int> first{int(upper.outerSize())};
  run_ranges(int(upper.outerSize()), 4096, [&](int lo, int hi) {
    for (int j = lo; j < hi && j < first.load(std::memory_order_relaxed); ++j)
      for (SpMat::InnerIterator it(upper, j); it; ++it)
        if (!std::isfinite(it.value())) {
          int seen = first.load();
          while (j < seen && !first.compare_exchange_weak(seen, j)) {  // first = min(first, j)
          }
          return;
        }
  });
  if (first.load() == upper.outerSize()) return;
  for (SpMat::InnerIterator it(upper, first.load()); it; ++it)
    if (!std::isfinite(it.value()))
      throw SolverError(
          fmt::format("{}: non-finite matrix entry {} at ({}, {})", who, it.value(), it.row(), first.load()));
}

void check_rhs(const DenseMat& B, Index n, const std::string& who) {
  if (B.rows() != n)
    throw SolverError(fmt::format("{}: right-hand side has {} rows, system has {}", who, B.rows(), n));
}

void check_finite_result(const DenseMat& X, const std::string& who) {
  if (!X.allFinite()) {
    Eigen::Index bad = 0;
    for (; bad < X.size(); ++bad)
      if (!std::isfinite(X.data()[bad])) break;
    throw SolverError(fmt::format("{}: solution is not finite (entry {} of column {} is {})", who,
                                  bad % X.rows(), bad / X.rows(), X.data()[bad]));
  }
}

void check_dense_budget(Index n, const std::string& who) {
  if (n > kMaxDenseUnknowns)
    throw BudgetError(fmt::format("{}: {} unknowns would need a {:.1f} GB dense matrix (limit {} unknowns)", who, n,
                                  double(n) * double(n) * 8.0 / 1e9, kMaxDenseUnknowns));
}

const SpMat& compressed(const SpMat& m, SpMat& storage) {
  if (m.isCompressed()) return m;
  storage = m;
  storage.makeCompressed();
  return storage;
}

SpMat full_from_upper(const SpMat& upper) {
  SpMat full = upper.selfadjointView<Eigen::Upper>();
  full.makeCompressed();
  return full;
}

DenseMat dense_from_upper(const SpMat& upper) {
  DenseMat dense = DenseMat::Zero(upper.rows(), upper.cols());
  for (Index j = 0; j < upper.outerSize(); ++j)
    for (SpMat::InnerIterator it(upper, j); it; ++it) {
      if (it.row() > j) continue;  // the contract passes the upper triangle; ignore anything below
      dense(it.row(), j) = it.value();
      dense(j, it.row()) = it.value();
    }
  return dense;
}

namespace {
constexpr std::uint64_t kPrime = 0x100000001b3ULL;

//! Hashes of parts mixed in their order into one, seeded with the element count.
template <class Hashes>
std::uint64_t mixed(std::size_t count, const Hashes& parts) {
  std::uint64_t x = count;
  for (std::uint64_t v : parts) x = (x ^ v) * kPrime ^ (x >> 29);
  return x;
}

//! 64-bit fingerprint of an index array: four independent FNV-style lanes (one dependent multiply chain
//! would be bound by the multiply's latency), mixed at the end.
std::uint64_t fingerprint(const int* a, std::size_t count) {
  std::uint64_t h[4] = {0xcbf29ce484222325ULL, 0x84222325cbf29ce4ULL, 0x9e3779b97f4a7c15ULL, 0xc2b2ae3d27d4eb4fULL};
  std::size_t i = 0;
  for (; i + 3 < count; i += 4)
    for (int k = 0; k < 4; ++k) h[k] = (h[k] ^ std::uint32_t(a[i + std::size_t(k)])) * kPrime;
  for (; i < count; ++i) h[0] = (h[0] ^ std::uint32_t(a[i])) * kPrime;
  return mixed(count, h);
}

//! fingerprint of fixed chunks on the worker threads, mixed in chunk order: the same value for any thread count
//! (a serial pass over a large factorization's indices is init time that does not shrink with cores).
std::uint64_t chunked_fingerprint(const int* a, std::size_t count) {
  constexpr std::size_t kChunk = std::size_t(1) << 20;
  std::vector<std::uint64_t> h((count + kChunk - 1) / kChunk);
  run_ranges(int(h.size()), 1, [&](int lo, int hi) {
    for (int c = lo; c < hi; ++c) {
      const std::size_t at = std::size_t(c) * kChunk;
      h[std::size_t(c)] = fingerprint(a + at, std::min(kChunk, count - at));
    }
  });
  return mixed(count, h);
}

std::uint64_t pattern_hash(const SpMat& upper) {
  return chunked_fingerprint(upper.outerIndexPtr(), std::size_t(upper.cols()) + 1) ^
         (chunked_fingerprint(upper.innerIndexPtr(), std::size_t(upper.nonZeros())) << 1);
}
}  // namespace

void PatternGuard::remember(const SpMat& upper) {
  n_ = std::size_t(upper.cols());
  nnz_ = std::size_t(upper.nonZeros());
  hash_ = pattern_hash(upper);
  set_ = true;
}

void PatternGuard::check(const SpMat& upper, const std::string& who) const {
  const std::size_t n = std::size_t(upper.cols()), nnz = std::size_t(upper.nonZeros());
  const bool same = set_ && n == n_ && nnz == nnz_ && pattern_hash(upper) == hash_;
  if (!same)
    throw SolverError(fmt::format("{}: factorize() got a different sparsity pattern than analyze() "
                                  "(n {} vs {}, nnz {} vs {}); call analyze() again",
                                  who, n, n_, nnz, nnz_));
}

DenseVec diagonal_of(const SpMat& upper) {
  // Each column's rows ascend (Eigen's compressed storage): its diagonal entries are its last ones (an upper
  // triangle's) or just before the rows below it, read backwards from the column's end. Column ranges on the
  // worker threads: a serial pass over a large matrix is init time that does not shrink with cores.
  DenseVec diag = DenseVec::Zero(upper.cols());
  const auto* p = upper.outerIndexPtr();
  const auto* rows = upper.innerIndexPtr();
  const double* values = upper.valuePtr();
  run_ranges(int(upper.outerSize()), 4096, [&](int lo, int hi) {
    for (int j = lo; j < hi; ++j) {
      const auto end = upper.isCompressed() ? p[j + 1] : p[j] + upper.innerNonZeroPtr()[j];
      for (auto k = end - 1; k >= p[j] && rows[k] >= j; --k)
        if (rows[k] == j) diag(j) += values[k];
    }
  });
  return diag;
}

double check_pivots(const std::vector<double>& pivots, const int* perm, const SpMat& upper, const std::string& who,
                    bool singular_test) {
  return check_pivots(pivots, perm, diagonal_of(upper), who, singular_test);
}

double check_pivots(const std::vector<double>& pivots, const int* perm, const DenseVec& diag, const std::string& who,
                    bool singular_test) {
  const Index n = diag.size();
  const double bound = singular_test ? singular_pivot_bound(std::size_t(n)) : 0.0;
  double smallest = std::numeric_limits<double>::infinity();
  for (Index k = 0; k < n; ++k) {
    const double d = pivots[std::size_t(k)];
    const double a = diag(perm ? perm[k] : k);
    if (!(d > 0) || !(a > 0))
      throw SolverError(fmt::format("{}: matrix not positive definite (pivot {:.3g} at column {} of {})", who, d, k, n));
    if (d / a < bound)
      throw SolverError(fmt::format("{}: matrix numerically singular (pivot {:.3g} at column {} of {} is {:.2g} "
                                    "of its diagonal entry)", who, d, k, n, d / a));
    smallest = std::min(smallest, d / a);
  }
  return smallest;
}

double cholesky_flops(const int* col_ptr, Index n) {
  double fl = 0;
  for (Index j = 0; j < n; ++j) {
    const double c = col_ptr[j + 1] - col_ptr[j];
    fl += c * c;
  }
  return fl;
}

const SpMat& prepare_factorize(LinearSolver& solver, const PatternGuard& guard, const SpMat& in, SpMat& storage) {
  const SpMat& upper = compressed(in, storage);
  if (guard.empty())
    solver.analyze(upper);
  else
    guard.check(upper, solver.name());
  check_finite_values(upper, solver.name());
  return upper;
}

BlockGraph block_graph(const SpMat& upper, int b) {
  BlockGraph g;
  const int nb = int(upper.cols()) / b;
  g.nb = nb;
  // Pass 1: distinct off-diagonal block rows of each block column (upper triangle as stored).
  std::vector<int> mark(static_cast<std::size_t>(nb), -1);
  std::vector<int> up(static_cast<std::size_t>(nb) + 1, 0), ui;
  ui.reserve(std::size_t(upper.nonZeros()) / std::size_t(b * b) + std::size_t(nb));
  for (int J = 0; J < nb; ++J) {
    for (int c = 0; c < b; ++c) {
      const int j = J * b + c;
      for (int p = upper.outerIndexPtr()[j]; p < upper.outerIndexPtr()[j + 1]; ++p) {
        const int I = upper.innerIndexPtr()[p] / b;
        if (I != J && mark[std::size_t(I)] != J) {
          mark[std::size_t(I)] = J;
          ui.push_back(I);
        }
      }
    }
    up[std::size_t(J) + 1] = int(ui.size());
  }
  // Pass 2: symmetrize (orderings want both triangles), then drop duplicates and sort each column.
  std::vector<int> cnt(static_cast<std::size_t>(nb) + 1, 0);
  for (int J = 0; J < nb; ++J)
    for (int p = up[std::size_t(J)]; p < up[std::size_t(J) + 1]; ++p) {
      ++cnt[std::size_t(J) + 1];
      ++cnt[std::size_t(ui[std::size_t(p)]) + 1];
    }
  for (int J = 0; J < nb; ++J) cnt[std::size_t(J) + 1] += cnt[std::size_t(J)];
  std::vector<int>& Ai = g.Ai;
  Ai.assign(static_cast<std::size_t>(cnt.back()), 0);
  std::vector<int> next(cnt.begin(), cnt.end() - 1);
  for (int J = 0; J < nb; ++J)
    for (int p = up[std::size_t(J)]; p < up[std::size_t(J) + 1]; ++p) {
      const int I = ui[std::size_t(p)];
      Ai[std::size_t(next[std::size_t(J)]++)] = I;
      Ai[std::size_t(next[std::size_t(I)]++)] = J;
    }
  g.Ap.assign(static_cast<std::size_t>(nb) + 1, 0);
  std::fill(mark.begin(), mark.end(), -1);
  int w = 0;
  for (int J = 0; J < nb; ++J) {
    const int start = w;
    for (int p = cnt[std::size_t(J)]; p < cnt[std::size_t(J) + 1]; ++p) {
      const int I = Ai[std::size_t(p)];
      if (mark[std::size_t(I)] != J) {
        mark[std::size_t(I)] = J;
        Ai[std::size_t(w++)] = I;
      }
    }
    std::sort(Ai.begin() + start, Ai.begin() + w);
    g.Ap[std::size_t(J) + 1] = w;
  }
  Ai.resize(static_cast<std::size_t>(w));
  return g;
}

}  // namespace db::solver_util
