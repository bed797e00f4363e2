// METIS's random draws kept per thread (solvers/ordering/metis_random.h): the interposed rand() is the one the
// dynamic linker resolves, draws glibc's sequence (its known first values after srand(1) and srand(42)), one
// sequence per thread, and METIS orderings computed on two threads at once are the serial ones.
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

TEST(MetisRandom, TheProcessResolvesTheInterposedGenerator) { EXPECT_TRUE(db::metis_draws_per_thread()); }

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

}  // namespace
