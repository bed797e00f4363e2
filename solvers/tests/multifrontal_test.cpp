// The multifrontal backend's parts below the LinearSolver interface: the update matrices' pool, the thread choice.
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "solvers/multifrontal/schedule.h"
#include "solvers/multifrontal/storage.h"

namespace {

using db::multifrontal::UpdateBlock;
using db::multifrontal::UpdatePool;

TEST(UpdatePool, FirstFitReusesAndCoalesces) {
  UpdatePool pool(1000 * 8);  // 1000 units of 8 doubles
  double* a = pool.take(100 * 8);
  double* b = pool.take(200 * 8);
  double* c = pool.take(300 * 8);
  ASSERT_TRUE(a && b && c);
  EXPECT_EQ(b, a + 100 * 8);
  EXPECT_EQ(c, b + 200 * 8);
  EXPECT_EQ(pool.take(401 * 8), nullptr);  // 400 units left
  pool.give(b, 200 * 8);
  EXPECT_EQ(pool.take(150 * 8), b);  // the lowest hole that fits
  double* d = pool.take(60 * 8);     // 50 units left in the hole: the range after c
  EXPECT_EQ(d, c + 300 * 8);
  pool.give(a, 100 * 8);
  pool.give(b, 150 * 8);
  pool.give(c, 300 * 8);
  pool.give(d, 60 * 8);
  EXPECT_EQ(pool.take(1000 * 8), a);  // all ranges merged back into one
}

TEST(UpdatePool, RoundsUpAndRefusesWhenClosedOrEmpty) {
  UpdatePool none(0);
  EXPECT_EQ(none.take(1), nullptr);
  UpdatePool pool(64);
  double* a = pool.take(1);  // one unit (8 doubles)
  double* b = pool.take(9);  // two
  ASSERT_TRUE(a && b);
  EXPECT_EQ(b, a + 8);
  pool.give(a, 1);
  pool.close();
  EXPECT_EQ(pool.take(1), nullptr);
  pool.give(b, 9);  // giving back after close is fine
}

TEST(UpdatePool, BlocksComeFromThePoolUntilItIsFull) {
  const int r = 40;  // 1600 entries, below the own-mapping size
  UpdatePool pool(3000);
  {
    UpdateBlock u(r, true, &pool);
    for (int j = 0; j < r; ++j)
      for (int i = j; i < r; ++i) ASSERT_EQ(u.col(j)[i - j], 0.0);
    u.col(3)[2] = 5.0;
    UpdateBlock v(r, false, &pool);  // 1600 > the 1400 left: from the heap
    UpdateBlock w = std::move(u);    // moving keeps the pool's block
    EXPECT_EQ(w.col(3)[2], 5.0);
    double* rest = pool.take(1400);  // v took nothing from the pool
    ASSERT_NE(rest, nullptr);
    pool.give(rest, 1400);
    EXPECT_EQ(pool.take(1401), nullptr);
  }
  EXPECT_NE(pool.take(3000), nullptr);  // returned on destruction
}

}  // namespace

// The solves' thread count by work (schedule.h): from 1 to the most allowed, never fewer for more work, and more
// than one exactly where worth_threads says a second thread is worth starting.
TEST(ThreadsWorth, BoundedMonotoneAndConsistentWithWorthThreads) {
  using db::multifrontal::threads_worth;
  using db::multifrontal::Work;
  for (Work kind : {Work::Solve, Work::Dense}) {
    int last = 1;
    for (double flops = 1; flops < 1e13; flops *= 3) {
      const int t = threads_worth(flops, kind, 16);
      EXPECT_GE(t, last) << flops;
      EXPECT_GE(t, 1);
      EXPECT_LE(t, 16);
      EXPECT_EQ(threads_worth(flops, kind, 1), 1);
      EXPECT_EQ(threads_worth(flops, kind, 2) > 1, db::multifrontal::worth_threads(flops, kind)) << flops;
      last = t;
    }
    EXPECT_EQ(threads_worth(1e13, kind, 16), 16);  // hours of one core's work
  }
}
