// The threaded adjacency lists (solvers/ordering/adjacency_lists.h) against the lists read off the graph's edge set:
// the same lists for any number of column ranges, on random upper patterns with the diagonal, entries below it
// (ignored), empty columns and isolated vertices, and on the empty graph.
#include <algorithm>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "solvers/ordering/adjacency_lists.h"

namespace {

//! A random n-vertex pattern in CSC, rows ascending: per column some entries above the diagonal, the diagonal
//! (mostly), and now and then one below it; and the edge set its upper triangle gives.
struct RandomPattern {
  int n;
  std::vector<int> colptr{0}, rows;
  std::set<std::pair<int, int>> edges;

  RandomPattern(int vertices, unsigned seed) : n(vertices) {
    std::mt19937 rng(seed);
    for (int j = 0; j < n; ++j) {
      std::set<int> column;
      const int above = j == 0 ? 0 : int(rng() % 7);
      for (int k = 0; k < above; ++k) column.insert(int(rng() % unsigned(j)));
      if (rng() % 8 != 0) column.insert(j);
      if (j + 1 < n && rng() % 10 == 0) column.insert(j + 1 + int(rng() % unsigned(n - j - 1)));
      for (const int r : column) {
        rows.push_back(r);
        if (r < j) edges.emplace(r, j);
      }
      colptr.push_back(int(rows.size()));
    }
  }
  db::GraphPattern pattern() const { return {n, colptr.data(), rows.data()}; }

  //! Each vertex's neighbours, ascending.
  db::AdjacencyLists reference() const {
    std::vector<std::vector<int>> lists(static_cast<std::size_t>(n));
    for (const auto& [a, b] : edges) {
      lists[std::size_t(a)].push_back(b);
      lists[std::size_t(b)].push_back(a);
    }
    db::AdjacencyLists h;
    for (auto& list : lists) {
      std::sort(list.begin(), list.end());
      h.adjncy.insert(h.adjncy.end(), list.begin(), list.end());
      h.xadj.push_back(int(h.adjncy.size()));
    }
    return h;
  }
};

TEST(AdjacencyLists, SameListsForAnyNumberOfRanges) {
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const RandomPattern g(1 + int(seed * 97 % 400), seed);
    const db::AdjacencyLists want = g.reference();
    for (int ranges : {1, 2, 3, 8, 1000}) {
      const db::AdjacencyLists got = db::adjacency_lists(g.pattern(), ranges);
      ASSERT_EQ(got.xadj, want.xadj) << "seed " << seed << ", " << ranges << " ranges";
      ASSERT_EQ(got.adjncy, want.adjncy) << "seed " << seed << ", " << ranges << " ranges";
    }
  }
}

TEST(AdjacencyLists, EmptyGraph) {
  const std::vector<int> colptr{0};
  const db::AdjacencyLists h = db::adjacency_lists({0, colptr.data(), nullptr}, 4);
  EXPECT_EQ(h.xadj, std::vector<int>{0});
  EXPECT_TRUE(h.adjncy.empty());
}

}  // namespace
