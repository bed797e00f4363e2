// The postorder of a dissected order found part by part (solvers/ordering/dissection_postorder.h) against its
// exact reference, CHOLMOD's postordered analysis of the whole graph under the same order: the same permutation on
// random dissection-shaped graphs (parts of several connected pieces, pieces with no separator neighbour,
// separators between and after the parts) at any thread count, with the elimination tree and column counts of the
// graph in that permutation (what the symbolic analysis may be handed); parts that touch refused. And order_graph,
// which uses it for METIS's dissected orders, against analyze_graph's permutation on a grid at 1-16 worker threads.
#include <algorithm>
#include <memory>
#include <numeric>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <cholmod.h>
#include <gtest/gtest.h>

#include "solvers/base/error.h"
#include "solvers/ordering/cholmod_views.h"
#include "solvers/ordering/dissection_postorder.h"
#include "solvers/ordering/graph_ordering.h"
#include "solvers/tests/worker_threads.h"

namespace {

//! An undirected graph as edge pairs, with its adjacency lists and the upper triangle (with the diagonal).
struct Graph {
  int n = 0;
  std::vector<std::pair<int, int>> edges;
  std::vector<int> ptr, adj, colptr, rows;

  void finish() {
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    std::vector<std::vector<int>> lists(static_cast<std::size_t>(n)), upper(static_cast<std::size_t>(n));
    for (const auto& [a, b] : edges) {
      lists[std::size_t(a)].push_back(b);
      lists[std::size_t(b)].push_back(a);
      upper[std::size_t(std::max(a, b))].push_back(std::min(a, b));
    }
    ptr.assign(1, 0);
    colptr.assign(1, 0);
    for (int v = 0; v < n; ++v) {
      std::sort(lists[std::size_t(v)].begin(), lists[std::size_t(v)].end());
      adj.insert(adj.end(), lists[std::size_t(v)].begin(), lists[std::size_t(v)].end());
      ptr.push_back(int(adj.size()));
      std::sort(upper[std::size_t(v)].begin(), upper[std::size_t(v)].end());
      rows.insert(rows.end(), upper[std::size_t(v)].begin(), upper[std::size_t(v)].end());
      rows.push_back(v);
      colptr.push_back(int(rows.size()));
    }
  }
  db::GraphPattern adjacency() const { return {n, ptr.data(), adj.data()}; }
  db::GraphPattern upper() const { return {n, colptr.data(), rows.data()}; }
};

//! The Perm of CHOLMOD's postordered simplicial analysis of g under `order`.
std::vector<int> cholmod_postordered(const Graph& g, std::vector<int> order) {
  cholmod_common cc;
  cholmod_start(&cc);
  const std::unique_ptr<cholmod_common, int (*)(cholmod_common*)> guard(&cc, cholmod_finish);
  cc.print = 0;
  cc.supernodal = CHOLMOD_SIMPLICIAL;
  cholmod_factor* L = db::analyze_graph_given(g.upper(), order, cc);
  const int* p = static_cast<const int*>(L->Perm);
  std::vector<int> perm(p, p + L->n);
  cholmod_free_factor(&L, &cc);
  return perm;
}

//! CHOLMOD's elimination tree and column counts of g in the order `order` (order[new] = old), from its analysis of
//! the graph renumbered, in natural order.
db::EliminationTree cholmod_tree(const Graph& g, const std::vector<int>& order) {
  std::vector<int> at(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) at[std::size_t(order[k])] = int(k);
  Graph renumbered;
  renumbered.n = g.n;
  for (const auto& [a, b] : g.edges)
    renumbered.edges.emplace_back(std::min(at[std::size_t(a)], at[std::size_t(b)]),
                                  std::max(at[std::size_t(a)], at[std::size_t(b)]));
  renumbered.finish();
  cholmod_common cc;
  cholmod_start(&cc);
  const std::unique_ptr<cholmod_common, int (*)(cholmod_common*)> guard(&cc, cholmod_finish);
  cc.print = 0;
  const auto n = std::size_t(g.n);
  db::EliminationTree tree{std::vector<int>(n), std::vector<int>(n), renumbered.rows.size()};
  std::vector<int> natural(n), post(n), first(n), level(n);
  std::iota(natural.begin(), natural.end(), 0);
  cholmod_sparse A = db::cholmod_upper_view(n, renumbered.colptr.data(), renumbered.rows.data(), nullptr);
  EXPECT_TRUE(n == 0 || cholmod_analyze_ordering(&A, CHOLMOD_NATURAL, natural.data(), nullptr, 0, tree.parent.data(),
                                                 post.data(), tree.count.data(), first.data(), level.data(), &cc));
  return tree;
}

//! A random graph shaped by a nested dissection: blocks of positions, each a part or a separator; edges within a
//! part (sparse, so that parts fall into several pieces, some isolated), from a part to later separators, and
//! between separators. The vertices are numbered at random (order maps positions to them).
struct RandomDissection {
  Graph g;
  std::vector<int> order;
  std::vector<db::PositionRange> parts;

  explicit RandomDissection(unsigned seed) {
    std::mt19937 rng(seed);
    const auto below = [&](unsigned k) { return int(rng() % k); };
    int n = 0;
    for (int b = 0, blocks = 3 + below(6); b < blocks; ++b) {
      const bool part = b == 0 || below(2) == 0;
      const int size = part ? 1 + below(30) : below(8);
      if (part) parts.push_back({n, n + size});
      n += size;
    }
    g.n = n;
    std::vector<char> in_part(static_cast<std::size_t>(n), 0);
    for (const db::PositionRange r : parts)
      for (int k = r.lo; k < r.hi; ++k) in_part[std::size_t(k)] = 1;
    std::vector<std::pair<int, int>> by_position;
    for (const db::PositionRange r : parts)
      for (int j = r.lo; j < r.hi; ++j) {
        for (int i = r.lo; i < j; ++i)
          if (below(8) == 0) by_position.emplace_back(i, j);
        for (int s = r.hi; s < n; ++s)
          if (!in_part[std::size_t(s)] && below(6) == 0) by_position.emplace_back(j, s);
      }
    for (int s = 0; s < n; ++s)
      for (int t = s + 1; t < n; ++t)
        if (!in_part[std::size_t(s)] && !in_part[std::size_t(t)] && below(4) == 0) by_position.emplace_back(s, t);
    order.resize(std::size_t(n));
    std::iota(order.begin(), order.end(), 0);
    for (int k = n - 1; k > 0; --k) std::swap(order[std::size_t(k)], order[std::size_t(below(unsigned(k) + 1))]);
    for (const auto& [i, j] : by_position) g.edges.emplace_back(order[std::size_t(i)], order[std::size_t(j)]);
    for (auto& [a, b] : g.edges)
      if (a > b) std::swap(a, b);
    g.finish();
  }
};

TEST(DissectionPostorder, SameAsCholmodsPostorderedAnalysisOnRandomDissections) {
  for (unsigned seed = 1; seed <= 200; ++seed) {
    const RandomDissection d(seed);
    const std::vector<int> reference = cholmod_postordered(d.g, d.order);
    const db::EliminationTree reference_tree = cholmod_tree(d.g, reference);
    for (int threads : {1, 3}) {
      db::EliminationTree tree;
      ASSERT_EQ(db::postorder_dissection(d.g.adjacency(), d.order, d.parts, threads, &tree), reference)
          << "seed " << seed << ", " << threads << " threads, " << d.g.n << " vertices, " << d.parts.size()
          << " parts";
      ASSERT_EQ(tree.parent, reference_tree.parent) << "seed " << seed << ", " << threads << " threads";
      ASSERT_EQ(tree.count, reference_tree.count) << "seed " << seed << ", " << threads << " threads";
      ASSERT_EQ(tree.upper_entries, reference_tree.upper_entries) << "seed " << seed;
    }
  }
}

TEST(DissectionPostorder, WholeGraphAsOnePartAndNoParts) {
  const RandomDissection d(7);
  const std::vector<int> reference = cholmod_postordered(d.g, d.order);
  EXPECT_EQ(db::postorder_dissection(d.g.adjacency(), d.order, {{0, d.g.n}}, 2), reference);
  EXPECT_EQ(db::postorder_dissection(d.g.adjacency(), d.order, {}, 2), reference);
}

TEST(DissectionPostorder, RefusesPartsThatAreNotSeparated) {
  // A path 0 - 1 - 2 in this order.
  Graph g;
  g.n = 3;
  g.edges = {{0, 1}, {1, 2}};
  g.finish();
  const std::vector<int> order{0, 1, 2};
  // Two parts joined by an edge.
  EXPECT_THROW(db::postorder_dissection(g.adjacency(), order, {{0, 1}, {1, 3}}, 1), db::SolverError);
  // A part whose neighbour outside it comes earlier.
  EXPECT_THROW(db::postorder_dissection(g.adjacency(), order, {{1, 3}}, 1), db::SolverError);
  // Overlapping or out-of-range parts, an order of another size.
  EXPECT_THROW(db::postorder_dissection(g.adjacency(), order, {{0, 2}, {1, 3}}, 1), db::SolverError);
  EXPECT_THROW(db::postorder_dissection(g.adjacency(), order, {{0, 4}}, 1), db::SolverError);
  EXPECT_THROW(db::postorder_dissection(g.adjacency(), {0, 1}, {}, 1), db::SolverError);
  // A part followed by its separator is accepted.
  EXPECT_EQ(db::postorder_dissection(g.adjacency(), order, {{0, 1}}, 1), cholmod_postordered(g, order));
}

using db::test::WorkerThreads;

//! A k x k grid whose vertices each neighbour the 8 around them: METIS dissects it from k = 142 on.
Graph grid(int k) {
  Graph g;
  g.n = k * k;
  for (int y = 0; y < k; ++y)
    for (int x = 0; x < k; ++x)
      for (const auto& [dx, dy] : {std::pair{1, 0}, {-1, 1}, {0, 1}, {1, 1}})
        if (x + dx >= 0 && x + dx < k && y + dy < k) g.edges.emplace_back(x + k * y, x + dx + k * (y + dy));
  g.finish();
  return g;
}

TEST(OrderGraph, SameAsAnalyzeGraphsPermutationAtAnyThreadCount) {
  const Graph g = grid(170);  // 28900 vertices: dissected, in two levels from four threads
  for (int threads : {1, 2, 4, 16}) {
    const WorkerThreads t(threads);
    cholmod_common cc;
    cholmod_start(&cc);
    const std::unique_ptr<cholmod_common, int (*)(cholmod_common*)> guard(&cc, cholmod_finish);
    cc.print = 0;
    cc.supernodal = CHOLMOD_SIMPLICIAL;
    for (const std::string method : {"metis", "amd"}) {
      cholmod_factor* L = db::analyze_graph(g.upper(), method, cc);
      const int* p = static_cast<const int*>(L->Perm);
      const std::vector<int> reference(p, p + L->n);
      cholmod_free_factor(&L, &cc);
      EXPECT_EQ(db::order_graph(g.upper(), method), reference) << method << ", " << threads << " threads";
    }
  }
}

}  // namespace
