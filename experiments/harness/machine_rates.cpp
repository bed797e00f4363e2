#include "harness/machine_rates.h"

#include <algorithm>
#include <functional>
#include <numeric>
#include <vector>

#include <sys/mman.h>

#include "solvers/base/error.h"
#include "solvers/base/resources.h"
#include "core/timer.h"
#include "solvers/base/types.h"
#include "solvers/blas_lapack.h"

namespace db::harness {
namespace {

double best_of(int reps, const std::function<void()>& f) {
  double best = 1e300;
  for (int i = 0; i < reps; ++i) {
    Timer t;
    f();
    best = std::min(best, t.seconds());
  }
  return best;
}

}  // namespace

MachineRates MachineRates::measure() {
  MachineRates r;
  {
    const int m = 384;
    const DenseMat A = DenseMat::Random(m, m), B = DenseMat::Random(m, m);
    DenseMat C(m, m);
    const double s = best_of(3, [&] { C.noalias() = A * B; });
    r.dense = 2.0 * m * m * m / s;
  }
  {
    // A grid operator shaped like a Laplacian (5 entries a row): the product A^T A the sparse builds perform.
    const int g = 300, n = g * g;
    std::vector<Eigen::Triplet<double, int>> t;
    t.reserve(5 * n);
    for (int i = 0; i < g; ++i)
      for (int j = 0; j < g; ++j) {
        const int v = i * g + j;
        t.emplace_back(v, v, 4.0);
        if (i > 0) t.emplace_back(v, v - g, -1.0);
        if (i + 1 < g) t.emplace_back(v, v + g, -1.0);
        if (j > 0) t.emplace_back(v, v - 1, -1.0);
        if (j + 1 < g) t.emplace_back(v, v + 1, -1.0);
      }
    SpMat A(n, n);
    A.setFromTriplets(t.begin(), t.end());
    double flops = 0;
    const SpMat At = A.transpose();
    for (int c = 0; c < At.outerSize(); ++c) {  // row c of A = column c of A^T
      const double k = At.outerIndexPtr()[c + 1] - At.outerIndexPtr()[c];
      flops += 2 * k * k;
    }
    SpMat P;
    const double s = best_of(3, [&] { P = SpMat(At * A); });
    r.sparse = flops / s;
  }
  {
    // 32 MB, well beyond the caches: forward/back substitution streams the factor the same way.
    const int m = 2048;
    const DenseMat A = DenseMat::Random(m, m);
    const DenseVec x = DenseVec::Random(m);
    DenseVec y(m);
    const double s = best_of(3, [&] { y.noalias() = A * x; });
    r.stream = 2.0 * m * m / s;
  }
  return r;
}

double MachineRates::blas_gemm(int m) {
  const DenseMat A = DenseMat::Random(m, m), B = DenseMat::Random(m, m);
  DenseMat C(m, m);
  auto gemm = [&] {
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, m, m, m, 1.0, A.data(), m, B.data(), m, 0.0, C.data(), m);
  };
  gemm();  // the BLAS's thread pool and the pages of C, outside the timing
  return 2.0 * m * m * m / best_of(3, gemm);
}

double MachineRates::read_bandwidth(std::size_t bytes) {
  const std::size_t count = std::max<std::size_t>(bytes / sizeof(double), 1024);
  std::vector<double> a(count, 1.0);
  const int T = std::max(1, worker_threads());
  std::vector<double> sums(static_cast<std::size_t>(T));
  auto read = [&] {
    run_on_threads(T, [&](int t) {
      const std::size_t lo = count * std::size_t(t) / std::size_t(T), hi = count * std::size_t(t + 1) / std::size_t(T);
      double s[4] = {};
      for (std::size_t i = lo; i + 3 < hi; i += 4)
        for (int k = 0; k < 4; ++k) s[k] += a[i + std::size_t(k)];
      sums[std::size_t(t)] = (s[0] + s[1]) + (s[2] + s[3]);
    });
  };
  read();
  const double seconds = best_of(3, read);
  if (std::accumulate(sums.begin(), sums.end(), 0.0) <= 0) throw Error("read_bandwidth: the sums were lost");
  return double(count * sizeof(double)) / seconds;
}

double MachineRates::first_touch(std::size_t bytes) {
  const std::size_t page = 4096, size = std::max(bytes, std::size_t(64) * page);
  void* map = mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (map == MAP_FAILED) throw Error("first_touch: cannot map the memory");
  advise_huge_pages(map, size);
  char* p = static_cast<char*>(map);
  const std::size_t pages = size / page;
  const int T = std::max(1, worker_threads());
  Timer t;
  run_on_threads(T, [&](int k) {
    for (std::size_t i = pages * std::size_t(k) / std::size_t(T); i < pages * std::size_t(k + 1) / std::size_t(T); ++i)
      p[i * page] = 1;
  });
  const double seconds = t.seconds();
  munmap(map, size);
  return double(size) / seconds;
}

}  // namespace db::harness
