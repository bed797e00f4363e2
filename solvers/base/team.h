#pragma once
//! A fixed set of threads that work through a sequence of short parallel steps together (the multifrontal
//! factorization's top phase: a few hundred steps, each a few dozen tiles of BLAS work on one front).
//!
//! Why not run_tasks (resources.h) per step: it starts its helper threads anew for every call, which costs more
//! than a step's work on many cores. Why not the BLAS's own threads: on fronts of a few thousand rows a
//! many-threaded dgemm divides each call too finely (its rate stayed flat from 8 to 16 threads on such fronts,
//! results/records/2026-11-26-threads). Why not an OpenMP pool: its threads keep spinning after the region.
//!
//! As with run_tasks, the caller never waits for a helper that has not started or is not scheduled: it claims
//! tiles itself and waits only for tiles a helper has claimed. Helpers spin briefly between steps, then sleep;
//! they are joined when the team is destroyed.
#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace db {

class Team {
 public:
  //! `threads` - 1 helpers start now (none for one thread; fewer where the system refuses more threads).
  explicit Team(int threads);
  ~Team();
  Team(const Team&) = delete;
  Team& operator=(const Team&) = delete;
  int size() const { return int(helpers_.size()) + 1; }

  //! fn(0) .. fn(tiles - 1), each exactly once, on the caller and on whichever helpers claim them; returns when all
  //! have finished. Tiles must be independent, compute the same on any thread, and not throw (a throw
  //! terminates). Only the team's creator calls run, one step at a time.
  void run(int tiles, const std::function<void(int)>& fn);

 private:
  //! The step's state in one word, so that a claim checks the step and its tile count at once: step number
  //! (upper 32 bits), tile count (16 bits), next unclaimed tile (lower 16 bits).
  static std::uint64_t pack(std::uint64_t step, int tiles, int next) {
    return step << 32 | std::uint64_t(tiles) << 16 | std::uint64_t(next);
  }
  //! Claims and runs the tiles of `step` until none is left unclaimed.
  void work(std::uint64_t step);
  void helper();

  std::atomic<std::uint64_t> state_{0};
  const std::function<void(int)>* fn_ = nullptr;  // the current step's; written before its state is published
  std::atomic<int> done_{0};                      // tiles of the current step finished
  std::atomic<int> sleepers_{0};
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::condition_variable wake_;
  std::vector<std::thread> helpers_;
};

//! `n` rows or columns cut into tiles of `width` for a team, left whole without one (no tile when n is 0): a
//! step's tiles are fixed by the work and the team's presence, never by its size, so its results are too.
struct Tiles {
  int n, step;
  Tiles(int n, int width, const Team* team) : n(n), step(team ? width : std::max(n, 1)) {}
  int count() const { return (n + step - 1) / step; }
  int first(int k) const { return k * step; }
  int size(int k) const { return std::min(step, n - k * step); }
  int end(int k) const { return first(k) + size(k); }
};

}  // namespace db
