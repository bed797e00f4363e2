#pragma once
//! DEFORMBENCH_THREADS set for a test's scope: the worker threads (solvers/base/resources.h), which set, among
//! others, how many levels the METIS dissection splits (solvers/ordering/graph_ordering.h).
#include <cstdlib>
#include <optional>
#include <string>

namespace db::test {

//! DEFORMBENCH_THREADS set to `threads` while it lives; the previous value (or none) restored after.
class WorkerThreads {
 public:
  explicit WorkerThreads(int threads) {
    if (const char* e = std::getenv("DEFORMBENCH_THREADS")) saved_ = e;
    setenv("DEFORMBENCH_THREADS", std::to_string(threads).c_str(), 1);
  }
  ~WorkerThreads() {
    if (saved_) setenv("DEFORMBENCH_THREADS", saved_->c_str(), 1);
    else unsetenv("DEFORMBENCH_THREADS");
  }
  WorkerThreads(const WorkerThreads&) = delete;
  WorkerThreads& operator=(const WorkerThreads&) = delete;

 private:
  std::optional<std::string> saved_;
};

}  // namespace db::test
