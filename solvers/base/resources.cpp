#include "solvers/base/resources.h"

#include <sched.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace db {
namespace {
std::size_t status_kib(const char* key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(key, 0) == 0) {
      std::istringstream is(line.substr(std::string(key).size()));
      std::size_t kib = 0;
      is >> kib;
      return kib;
    }
  }
  return 0;
}
}  // namespace

std::size_t peak_rss_bytes() { return status_kib("VmHWM:") * 1024; }
std::size_t current_rss_bytes() { return status_kib("VmRSS:") * 1024; }
std::size_t physical_memory_bytes() {
  return static_cast<std::size_t>(::sysconf(_SC_PHYS_PAGES)) * static_cast<std::size_t>(::sysconf(_SC_PAGE_SIZE));
}

int worker_threads() {
  if (const char* e = std::getenv("DEFORMBENCH_THREADS")) {
    const int t = std::atoi(e);
    if (t >= 1) return t;
  }
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

int available_cores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (::sched_getaffinity(0, sizeof(set), &set) == 0) return std::max(1, CPU_COUNT(&set));
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

void run_on_threads(int threads, const std::function<void(int)>& fn) {
  std::exception_ptr error;
  std::mutex error_mutex;
  auto guarded = [&](int t) {
    try {
      fn(t);
    } catch (...) {
      std::lock_guard<std::mutex> lock(error_mutex);
      if (!error) error = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(guarded, t);
  if (threads >= 1) guarded(0);
  for (auto& th : pool) th.join();
  if (error) std::rethrow_exception(error);
}

namespace {

//! One run_tasks call's state, shared with its helpers: a helper that starts after the last task was claimed
//! finds nothing to do and only touches this (kept alive by its shared_ptr), never the caller's frame.
struct TaskJob {
  const std::function<void(int)>* fn = nullptr;
  int tasks = 0;
  std::atomic<int> next{0};
  std::atomic<bool> failed{false};
  int finished = 0;  // guarded by mutex
  std::exception_ptr error;
  std::mutex mutex;
  std::condition_variable all_done;

  //! Claims and runs tasks until none is left.
  void work() {
    for (int t; (t = next.fetch_add(1)) < tasks;) {
      std::exception_ptr e;
      if (!failed.load())
        try {
          (*fn)(t);
        } catch (...) {
          e = std::current_exception();
          failed = true;
        }
      std::lock_guard<std::mutex> lock(mutex);
      if (e && !error) error = e;
      if (++finished == tasks) all_done.notify_all();
    }
  }
};

}  // namespace

void run_tasks(int tasks, const std::function<void(int)>& fn) {
  if (tasks <= 0) return;
  if (tasks == 1) return fn(0);
  auto job = std::make_shared<TaskJob>();
  job->fn = &fn;
  job->tasks = tasks;
  for (int h = 1; h < tasks; ++h) std::thread([job] { job->work(); }).detach();
  job->work();
  std::unique_lock<std::mutex> lock(job->mutex);
  job->all_done.wait(lock, [&] { return job->finished == tasks; });
  if (job->error) std::rethrow_exception(job->error);
}

void run_ranges(int n, int grain, const std::function<void(int, int)>& fn) {
  const int ranges = std::max(1, std::min(worker_threads(), n / std::max(grain, 1)));
  run_tasks(ranges, [&](int t) {
    fn(static_cast<int>(std::int64_t(n) * t / ranges), static_cast<int>(std::int64_t(n) * (t + 1) / ranges));
  });
}

std::vector<int> balanced_columns(const int* colptr, int first, int last, int parts) {
  std::vector<int> at(std::size_t(std::max(parts, 1)) + 1, last);
  at[0] = first;
  const std::int64_t base = colptr[first], entries = std::int64_t(colptr[last]) - base;
  for (std::size_t t = 1; t + 1 < at.size(); ++t) {
    const std::int64_t want = base + entries * std::int64_t(t) / std::int64_t(at.size() - 1);
    at[t] = std::max(at[t - 1], int(std::lower_bound(colptr + first, colptr + last, want) - colptr));
  }
  return at;
}

void advise_huge_pages(void* p, std::size_t bytes) {
#ifdef MADV_HUGEPAGE
  constexpr std::uintptr_t kHuge = std::uintptr_t(2) << 20;
  const std::uintptr_t lo = (reinterpret_cast<std::uintptr_t>(p) + kHuge - 1) & ~(kHuge - 1);
  const std::uintptr_t hi = (reinterpret_cast<std::uintptr_t>(p) + bytes) & ~(kHuge - 1);
  if (hi > lo) ::madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_HUGEPAGE);
#else
  (void)p;
  (void)bytes;
#endif
}

}  // namespace db
