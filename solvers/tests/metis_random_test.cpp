// METIS on threads (solvers/ordering/metis_random.h): the interposed rand() is the one the dynamic linker
// resolves, draws glibc's sequence (its known first values after srand(1) and srand(42)), one sequence per thread,
// and METIS orderings computed on two threads at once are the serial ones; METIS calls on two threads at once
// leave the process's SIGINT, SIGTERM and SIGABRT handlers as they were, and signal() from elsewhere still works.
#include <signal.h>

#include <cstdlib>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "solvers/ordering/graph_ordering.h"
#include "solvers/ordering/metis_random.h"

namespace {

//! The first `count` draws after srand(seed), on this thread.
std::vector<int> draws(unsigned seed, int count) {
  std::srand(seed);
  std::vector<int> out;
  for (int k = 0; k < count; ++k) out.push_back(std::rand());
  return out;
}

//! Upper triangle with the diagonal of a k x k grid's 9-point pattern, a planar graph METIS dissects.
struct Grid {
  std::vector<int> colptr{0}, rows;
  explicit Grid(int k) {
    for (int j = 0; j < k * k; ++j) {
      const int x = j % k, y = j / k;
      for (int dy = -1; dy <= 0; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int i = (y + dy) * k + (x + dx);
          if (x + dx >= 0 && x + dx < k && y + dy >= 0 && i <= j) rows.push_back(i);
        }
      colptr.push_back(int(rows.size()));
    }
  }
  db::GraphPattern pattern() const { return {int(colptr.size()) - 1, colptr.data(), rows.data()}; }
};

TEST(MetisRandom, TheProcessResolvesTheInterposedGenerator) { EXPECT_TRUE(db::metis_on_threads()); }

TEST(MetisRandom, DrawsGlibcsSequence) {
  // glibc's rand() after srand(1): the values every glibc program prints (its TYPE_3 additive generator).
  EXPECT_EQ(draws(1, 3), (std::vector<int>{1804289383, 846930886, 1681692777}));
  EXPECT_EQ(draws(42, 3), (std::vector<int>{71876166, 708592740, 1483128881}));
}

TEST(MetisRandom, EachThreadDrawsItsOwnSequence) {
  const int count = 300000;  // a few milliseconds: the two threads draw at the same time
  const std::vector<int> a = draws(7, count), b = draws(11, count);
  for (int round = 0; round < 5; ++round) {
    std::vector<int> got_a, got_b;
    std::thread other([&] { got_b = draws(11, count); });
    got_a = draws(7, count);
    other.join();
    EXPECT_EQ(got_a, a) << "round " << round;
    EXPECT_EQ(got_b, b) << "round " << round;
  }
}

TEST(MetisRandom, OrderingsOnTwoThreadsAtOnceAreTheSerialOnes) {
  // Below the dissection's size: each call is one METIS_NodeND, which reseeds and draws throughout.
  const Grid g1(60), g2(70);
  const std::vector<int> serial1 = db::metis_permutation(g1.pattern()), serial2 = db::metis_permutation(g2.pattern());
  for (int round = 0; round < 4; ++round) {
    std::vector<int> p1, p2;
    std::thread other([&] { p2 = db::metis_permutation(g2.pattern()); });
    p1 = db::metis_permutation(g1.pattern());
    other.join();
    EXPECT_EQ(p1, serial1) << "round " << round;
    EXPECT_EQ(p2, serial2) << "round " << round;
  }
}

void handler_a(int) {}
void handler_b(int) {}

//! The handler each of SIGINT, SIGTERM and SIGABRT has now.
std::vector<void (*)(int)> handlers() {
  std::vector<void (*)(int)> out;
  for (int sig : {SIGINT, SIGTERM, SIGABRT}) {
    struct sigaction now {};
    sigaction(sig, nullptr, &now);
    out.push_back(now.sa_handler);
  }
  return out;
}

TEST(MetisRandom, MetisOnTwoThreadsLeavesTheSignalHandlersInPlace) {
  struct sigaction sa {}, saved[3];
  sa.sa_handler = handler_a;
  sigemptyset(&sa.sa_mask);
  const int sigs[3] = {SIGINT, SIGTERM, SIGABRT};
  for (int k = 0; k < 3; ++k) sigaction(sigs[k], &sa, &saved[k]);
  const std::vector<void (*)(int)> before = handlers();
  const Grid g1(40), g2(45);
  // Before the interposition, two calls at once left METIS's handler in place in about one round of four.
  for (int round = 0; round < 40; ++round) {
    std::thread other([&] { db::metis_permutation(g2.pattern()); });
    db::metis_permutation(g1.pattern());
    other.join();
    ASSERT_EQ(handlers(), before) << "round " << round;
  }
  // ISO C's signal() (what METIS calls) from outside METIS is glibc's: it installs the handler and returns the one
  // it replaced.
  EXPECT_EQ(__sysv_signal(SIGINT, handler_b), &handler_a);
  EXPECT_EQ(handlers()[0], &handler_b);
  for (int k = 0; k < 3; ++k) sigaction(sigs[k], &saved[k], nullptr);
}

}  // namespace
