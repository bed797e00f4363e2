#include "solvers/base/team.h"

#include <algorithm>
#include <chrono>
#include <system_error>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace db {
namespace {

inline void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
  _mm_pause();
#endif
}

//! How long a helper spins for the next step before it sleeps: longer than the serial work between two steps
//! of a front (a panel's dpotrf), shorter than a scheduler slice.
constexpr auto kSpin = std::chrono::microseconds(200);
constexpr int kMostTiles = 0xffff;  // the tile fields of the packed state

}  // namespace

Team::Team(int threads) {
  for (int h = 1; h < threads; ++h) {
    try {
      helpers_.emplace_back([this] { helper(); });
    } catch (const std::system_error&) {
      break;  // no more threads to be had: fewer helpers, the same results
    }
  }
}

Team::~Team() {
  stop_.store(true);
  { const std::lock_guard<std::mutex> lock(mutex_); }
  wake_.notify_all();
  for (auto& h : helpers_) h.join();
}

void Team::run(int tiles, const std::function<void(int)>& fn) {
  if (helpers_.empty() || tiles <= 1) {
    for (int t = 0; t < tiles; ++t) fn(t);
    return;
  }
  for (int first = 0; first < tiles; first += kMostTiles) {  // steps of at most kMostTiles tiles
    const int count = std::min(kMostTiles, tiles - first);
    const std::function<void(int)> part = [&fn, first](int t) { fn(first + t); };
    fn_ = first == 0 && count == tiles ? &fn : &part;
    done_.store(0, std::memory_order_relaxed);
    const std::uint64_t step = (state_.load(std::memory_order_relaxed) >> 32) + 1;
    state_.store(pack(step, count, 0));  // seq_cst: ordered against a helper's sleepers_ count (helper())
    if (sleepers_.load() > 0) {
      { const std::lock_guard<std::mutex> lock(mutex_); }
      wake_.notify_all();
    }
    work(step);
    // What is left was claimed by a helper: wait for it, and for nothing else.
    for (int spins = 0; done_.load(std::memory_order_acquire) < count; ++spins)
      if (spins < 4096)
        cpu_relax();
      else
        std::this_thread::yield();
  }
}

void Team::work(std::uint64_t step) {
  for (;;) {
    std::uint64_t v = state_.load(std::memory_order_acquire);
    const int tiles = int(v >> 16 & 0xffff), next = int(v & 0xffff);
    if ((v >> 32) != step || next >= tiles) return;
    if (!state_.compare_exchange_weak(v, v + 1, std::memory_order_acq_rel)) continue;
    (*fn_)(next);  // the step cannot end, nor fn_ change, before this tile is counted done
    done_.fetch_add(1, std::memory_order_release);
  }
}

void Team::helper() {
  std::uint64_t seen = 0;
  for (;;) {
    std::uint64_t step = seen;
    const auto until = std::chrono::steady_clock::now() + kSpin;
    for (int spins = 0; step == seen && !stop_.load(std::memory_order_relaxed); ++spins) {
      step = state_.load(std::memory_order_acquire) >> 32;
      if (step == seen && (spins & 63) == 63 && std::chrono::steady_clock::now() > until) break;
      cpu_relax();
    }
    if (step == seen && !stop_.load()) {
      std::unique_lock<std::mutex> lock(mutex_);
      sleepers_.fetch_add(1);  // seq_cst, before the state is read again: run() either sees it or we see the step
      wake_.wait(lock, [&] { return stop_.load() || (state_.load() >> 32) != seen; });
      sleepers_.fetch_sub(1);
      step = state_.load(std::memory_order_acquire) >> 32;
    }
    if (stop_.load()) return;
    seen = step;
    work(step);
  }
}

}  // namespace db
