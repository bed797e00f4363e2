#include "harness/thread_policy.h"

#include <cstdlib>

#include <fmt/format.h>

namespace db::harness {

std::string ThreadSettings::text() const { return fmt::format("omp={} blas={} own={}", omp, blas, own); }

ThreadSettings thread_settings(const std::string& backend, int threads) {
  const int t = threads < 1 ? 1 : threads;
  if (backend.rfind("mumps", 0) == 0) return {t, 1, t};
  return {1, t, t};
}

void export_thread_settings(const ThreadSettings& s) {
  ::setenv("OMP_NUM_THREADS", std::to_string(s.omp).c_str(), 1);
  ::setenv("OPENBLAS_NUM_THREADS", std::to_string(s.blas).c_str(), 1);
  ::setenv("DEFORMBENCH_THREADS", std::to_string(s.own).c_str(), 1);
}

}  // namespace db::harness
