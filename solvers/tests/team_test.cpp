// The top phase's thread team (solvers/base/team.h): every tile of every step runs exactly once, a step sees all
// of the step before it, the helpers take part (also after sleeping between steps), and steps of more tiles than
// the packed state holds are cut, not lost.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "solvers/base/team.h"

namespace {

// Step k maps x to y (y[i] = x[i] + 3 x[(i + 1) % n] + k, integers, exact) and the next step maps y back: a tile
// reading its neighbour's entry before the previous step wrote it gives another sum than the serial run.
TEST(Team, StepsRunEachTileOnceAndInOrder) {
  for (int threads : {1, 2, 3, 5}) {
    const int n = 97;
    std::vector<std::int64_t> serial(n), x(n);
    for (int i = 0; i < n; ++i) serial[std::size_t(i)] = x[std::size_t(i)] = i % 7;
    std::vector<std::int64_t> sy(n), y(n);
    std::vector<std::atomic<int>> runs(n);
    db::Team team(threads);
    EXPECT_EQ(team.size(), threads);
    for (int k = 0; k < 400; ++k) {
      for (auto& r : runs) r = 0;
      auto& from = k % 2 ? y : x;
      auto& to = k % 2 ? x : y;
      team.run(n, [&](int i) {
        ++runs[std::size_t(i)];
        to[std::size_t(i)] = (from[std::size_t(i)] + 3 * from[std::size_t((i + 1) % n)] + k) % 1000003;
      });
      auto& sfrom = k % 2 ? sy : serial;
      auto& sto = k % 2 ? serial : sy;
      for (int i = 0; i < n; ++i)
        sto[std::size_t(i)] = (sfrom[std::size_t(i)] + 3 * sfrom[std::size_t((i + 1) % n)] + k) % 1000003;
      for (int i = 0; i < n; ++i) ASSERT_EQ(runs[std::size_t(i)].load(), 1) << "step " << k << " tile " << i;
      ASSERT_EQ(to, sto) << threads << " threads, step " << k;
    }
    for (int tiles : {0, 1, 2})  // nothing to share; one tile on the caller
      team.run(tiles, [&](int i) { ++runs[std::size_t(i)]; });
  }
}

TEST(Team, MoreTilesThanOneStepHolds) {
  const int tiles = 70000 + 13;  // over the 16-bit tile fields
  std::vector<std::atomic<int>> runs(tiles);
  db::Team team(3);
  team.run(tiles, [&](int i) { ++runs[std::size_t(i)]; });
  for (int i = 0; i < tiles; ++i) ASSERT_EQ(runs[std::size_t(i)].load(), 1) << i;
}

// Tile 0 waits until tile 1 has started, which only another thread can do while tile 0 runs: so a helper takes
// part. Between the steps the team idles longer than its helpers spin, so they must be woken from their sleep.
// The wait is bounded (a machine that never schedules the helper fails the test rather than hanging it).
TEST(Team, HelpersTakePartAfterSleeping) {
  db::Team team(2);
  for (int round = 0; round < 5; ++round) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    std::atomic<bool> second{false}, met{false};
    team.run(2, [&](int i) {
      if (i == 1) {
        second = true;
        return;
      }
      const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(20);
      while (!second && std::chrono::steady_clock::now() < until) std::this_thread::yield();
      met = second.load();
    });
    EXPECT_TRUE(met) << "round " << round;
  }
}

}  // namespace
