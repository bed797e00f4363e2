// The multifrontal backend's parts below the LinearSolver interface: the update matrices' pool, the thread choice,
// the top phase's tiles and teams.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <memory>
#include <mutex>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "solvers/base/error.h"
#include "solvers/base/team.h"
#include "solvers/multifrontal/front.h"
#include "solvers/multifrontal/matrix_chunk.h"
#include "solvers/multifrontal/schedule.h"
#include "solvers/multifrontal/storage.h"
#include "solvers/multifrontal/symbolic.h"
#include "solvers/multifrontal/top_phase.h"
#include "solvers/ordering/graph_ordering.h"
#include "solvers/tests/worker_threads.h"

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

// The solves' top team (schedule.h): never more threads than the plan was made for, nor than the cores, nor than
// the top's work is worth; serial rather than a team of two; and a top worth every thread gets the fewer of the
// plan's threads and the cores.
TEST(SolveTopTeam, NoMoreThanThePlansThreadsTheCoresOrTheWork) {
  using db::multifrontal::solve_top_team;
  using db::multifrontal::threads_worth;
  using db::multifrontal::Work;
  for (int plan = 1; plan <= 64; plan *= 2)
    for (int cores : {1, 2, 3, 8, 16, 64})
      for (double work = 1; work < 1e13; work *= 7) {
        const int team = solve_top_team(work, plan, cores);
        EXPECT_GE(team, 1);
        EXPECT_NE(team, 2) << plan << " " << cores << " " << work;
        EXPECT_LE(team, std::max(1, std::min({plan, cores, threads_worth(work, Work::Solve, 64)})));
      }
  EXPECT_EQ(solve_top_team(1e13, 8, 16), 8);  // the 8-thread plan at 16 threads keeps the 8-thread team
  EXPECT_EQ(solve_top_team(1e13, 16, 16), 16);
  EXPECT_EQ(solve_top_team(1e13, 16, 4), 4);
  EXPECT_EQ(solve_top_team(1e13, 16, 2), 1);
  EXPECT_EQ(solve_top_team(1e13, 2, 16), 1);
}

namespace {

//! Upper triangle of the graph Laplacian of a g x h grid plus the identity.
db::SpMat grid_upper(int g, int h) {
  std::vector<Eigen::Triplet<double>> t;
  for (int x = 0; x < g; ++x)
    for (int y = 0; y < h; ++y) {
      const int v = x * h + y;
      t.emplace_back(v, v, 5.0);
      if (x + 1 < g) t.emplace_back(v, v + h, -1.0);
      if (y + 1 < h) t.emplace_back(v, v + 1, -1.0);
    }
  db::SpMat U(g * h, g * h);
  U.setFromTriplets(t.begin(), t.end());
  return U;
}

//! Each supernode's factor entries: the solves' cost, a plan's cost in these tests.
std::vector<double> entry_costs(const db::multifrontal::Symbolic& S) {
  std::vector<double> cost(std::size_t(S.nsuper()));
  for (int s = 0; s < S.nsuper(); ++s) cost[std::size_t(s)] = double(S.xptr[std::size_t(s) + 1] - S.xptr[std::size_t(s)]);
  return cost;
}

//! `U` (an upper triangle) with each entry a dense b x b block: the pattern of a block (vertex) system such as TF's.
db::SpMat blocks_of(const db::SpMat& U, int b) {
  std::vector<Eigen::Triplet<double>> t;
  for (int j = 0; j < U.outerSize(); ++j)
    for (db::SpMat::InnerIterator it(U, j); it; ++it)
      for (int c = 0; c < b; ++c)
        for (int r = 0; r < b; ++r)
          if (it.row() < j || r <= c) t.emplace_back(b * int(it.row()) + r, b * j + c, it.value() + (r == c ? 1.0 : 0.1));
  db::SpMat B(b * U.rows(), b * U.cols());
  B.setFromTriplets(t.begin(), t.end());
  return B;
}

//! grid_upper(g, g) in 3x3 or other b x b blocks.
db::SpMat block_grid_upper(int g, int b) { return blocks_of(grid_upper(g, g), b); }

//! The upper triangle of the symmetric matrix whose upper triangle is `U`, in the order `perm` (perm[new] = old).
db::SpMat permuted_upper(const db::SpMat& U, const std::vector<int>& perm) {
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> to_new(int(perm.size()));
  for (std::size_t k = 0; k < perm.size(); ++k) to_new.indices()[perm[k]] = int(k);
  db::SpMat full;
  full = U.selfadjointView<Eigen::Upper>().twistedBy(to_new);
  db::SpMat upper = full.triangularView<Eigen::Upper>();
  upper.makeCompressed();
  return upper;
}

//! Whether two symbolic analyses are the same in every array.
void expect_same_symbolic(const db::multifrontal::Symbolic& a, const db::multifrontal::Symbolic& b,
                          const std::string& what) {
  EXPECT_EQ(a.n, b.n) << what;
  EXPECT_EQ(a.perm, b.perm) << what;
  EXPECT_EQ(a.col0, b.col0) << what;
  EXPECT_EQ(a.rptr, b.rptr) << what;
  EXPECT_EQ(a.rows, b.rows) << what;
  EXPECT_EQ(a.xptr, b.xptr) << what;
  EXPECT_EQ(a.parent, b.parent) << what;
  EXPECT_EQ(a.first, b.first) << what;
  EXPECT_EQ(a.cptr, b.cptr) << what;
  EXPECT_EQ(a.child, b.child) << what;
  EXPECT_EQ(a.nnz, b.nnz) << what;
  EXPECT_EQ(a.flops, b.flops) << what;
}

}  // namespace

// The symbolic analysis compresses the pattern to its blocks and expands CHOLMOD's supernodes on the worker
// threads (in ranges of columns and of supernodes): the result must not depend on how many there are, and each
// supernode's rows must ascend (the extend-add relies on it). A grid large enough for several threads' ranges.
TEST(AnalyzeBlocks, SameOnAnyThreadCountWithAscendingRows) {
  using namespace db::multifrontal;
  const db::SpMat U = block_grid_upper(220, 3);
  ASSERT_GT(U.nonZeros(), 1 << 20);  // above the grain at which the loops take a second thread
  const auto analyze_on = [&](const char* threads) {
    const db::test::WorkerThreads scope(std::atoi(threads));
    return analyze_blocks(U, 3, "amd");
  };
  const Symbolic one = analyze_on("1");
  ASSERT_GT(one.rows.size(), std::size_t(1) << 19);  // two threads expand its supernodes
  for (const char* threads : {"2", "3", "8"}) {
    const Symbolic S = analyze_on(threads);
    EXPECT_EQ(S.perm, one.perm) << threads;
    EXPECT_EQ(S.col0, one.col0) << threads;
    EXPECT_EQ(S.rptr, one.rptr) << threads;
    EXPECT_EQ(S.rows, one.rows) << threads;
    EXPECT_EQ(S.xptr, one.xptr) << threads;
    EXPECT_EQ(S.parent, one.parent) << threads;
    EXPECT_EQ(S.nnz, one.nnz) << threads;
  }
  ASSERT_EQ(one.n, int(U.cols()));
  for (int s = 0; s < one.nsuper(); ++s) {
    const int* R = one.rows.data() + one.rptr[std::size_t(s)];
    EXPECT_TRUE(std::is_sorted(R, R + one.nrows(s))) << s;
    for (int k = 0; k < one.ncols(s); ++k) ASSERT_EQ(R[k], one.col0[std::size_t(s)] + k) << s;  // own columns first
  }
}

// A dissected METIS ordering (20000 vertices or more) finds the graph's elimination tree and column counts part by
// part (solvers/ordering/dissection_postorder.h); handed to the symbolic analysis (SolverOptions::elimination_tree)
// they must give exactly what CHOLMOD's own pass over the ordered graph gives, for scalar and 3x3-block systems, at
// any thread count.
TEST(AnalyzeBlocks, TheOrderingsTreeGivesCholmodsOwnAnalysis) {
  using namespace db::multifrontal;
  const db::SpMat U = grid_upper(150, 150);  // 22500 vertices: METIS dissects it
  const db::GraphPattern g{int(U.cols()), U.outerIndexPtr(), U.innerIndexPtr()};
  for (const char* threads : {"1", "2", "4", "16"}) {
    const db::test::WorkerThreads scope(std::atoi(threads));
    db::EliminationTree tree;
    const db::SpMat P = permuted_upper(U, db::order_graph(g, "metis", nullptr, &tree));
    ASSERT_EQ(tree.parent.size(), std::size_t(U.cols())) << threads;
    for (int b : {1, 3}) {
      const db::SpMat Pb = b == 1 ? P : blocks_of(P, b);
      expect_same_symbolic(analyze_blocks(Pb, b, "natural", &tree), analyze_blocks(Pb, b, "natural"),
                           std::string(threads) + " threads, blocks of " + std::to_string(b));
    }
  }
}

// A given tree that cannot be the graph's is refused before CHOLMOD reads it (check_tree): another graph's size or
// entries, a parent before its child, a subtree out of order, an edge leaving a subtree, a count out of place. The
// graph: the path 0 - 1 - 2 - 3 in natural order, whose tree is the path and whose counts are 2, 2, 2, 1.
TEST(AnalyzeBlocks, RefusesAGivenTreeThatDoesNotFit) {
  using namespace db::multifrontal;
  const db::SpMat path = grid_upper(1, 4);
  const db::EliminationTree right{{1, 2, 3, -1}, {2, 2, 2, 1}, 7};
  expect_same_symbolic(analyze_blocks(path, 1, "natural", &right), analyze_blocks(path, 1, "natural"), "the path");
  const auto refused = [&](db::EliminationTree t, const char* what) {
    EXPECT_THROW(analyze_blocks(path, 1, "natural", &t), db::SolverError) << what;
  };
  refused({{1, 2, -1}, {2, 2, 1}, 5}, "another graph's size");
  refused({{1, 2, 3, -1}, {2, 2, 2, 1}, 8}, "another graph's entries");
  refused({{1, 0, 3, -1}, {2, 2, 2, 1}, 7}, "a parent before its child");
  refused({{2, 2, 3, -1}, {2, 2, 2, 1}, 7}, "edge (0, 1) leaves node 1's subtree");
  refused({{2, 3, 3, -1}, {2, 2, 2, 1}, 7}, "node 2's subtree, 0 and 2, is not contiguous");
  refused({{1, 2, 3, -1}, {2, 2, 2, 2}, 7}, "a root's count above 1");
  refused({{1, 2, 3, -1}, {2, 2, 3, 1}, 7}, "a count beyond the columns left");
  refused({{1, 2, 3, -1}, {3, 1, 2, 1}, 7}, "a count below 2 off the root, or more than one above its parent's");
  EXPECT_NO_THROW(analyze_blocks(path, 1, "amd", &right)) << "taken only for the natural order";
}

// The solves' plan (schedule.h): never a longer critical path than the plan for the most threads allowed, the
// fewest threads within 3% of the shortest path among the candidates, and one thread for a chain of supernodes
// (nothing to run in parallel).
TEST(ShortestPlan, NoLongerPathThanTheMostThreadsAndOneThreadForAChain) {
  using namespace db::multifrontal;
  const auto path = [](const Symbolic& S, const Plan& p, const std::vector<double>& cost) {
    const PlanCounts c = plan_counts(S, p, cost);
    return c.group_max + c.top;
  };
  const int g = 40;  // a 2-D grid Laplacian: a tree with parallelism at every level
  const Symbolic S = analyze_blocks(grid_upper(g, g), 1, "metis");
  const std::vector<double> cost = entry_costs(S);
  for (int most : {1, 2, 3, 8, 16}) {
    const SolvePlan best = shortest_plan(S, most, cost);
    EXPECT_GE(best.threads, 1);
    EXPECT_LE(best.threads, most);
    EXPECT_EQ(best.plan.subtrees.size(), std::size_t(best.threads));
    const double chosen = path(S, best.plan, cost);
    EXPECT_LE(chosen, 1.03 * path(S, schedule(S, most, cost), cost)) << most;
    for (int T = 1; T < best.threads; T *= 2) EXPECT_GT(path(S, schedule(S, T, cost), cost), chosen / 1.03) << T;
    // This grid's plan for 16 threads opens so many subtrees that its serial top outweighs what they take over.
    if (most == 16) {
      EXPECT_LT(chosen, path(S, schedule(S, most, cost), cost));
    }
  }
  const Symbolic chain = analyze_blocks(grid_upper(1, 200), 1, "natural");  // a path graph in natural order
  std::vector<double> ones(std::size_t(chain.nsuper()), 1.0);
  EXPECT_EQ(shortest_plan(chain, 16, ones).threads, 1);
}

// The factorization's claim order (schedule.h): every subtree root of the plan once, costliest first.
TEST(ClaimOrder, EveryRootOnceCostliestFirst) {
  using namespace db::multifrontal;
  const Symbolic S = analyze_blocks(grid_upper(40, 40), 1, "metis");
  const std::vector<double> cost = entry_costs(S);
  for (int T : {1, 2, 5, 16}) {
    const Plan plan = schedule(S, T, cost);
    std::vector<int> roots, order = claim_order(S, plan, cost);
    for (const auto& group : plan.subtrees) roots.insert(roots.end(), group.begin(), group.end());
    std::vector<int> sorted = order;
    std::sort(roots.begin(), roots.end());
    std::sort(sorted.begin(), sorted.end());
    EXPECT_EQ(sorted, roots) << T;
    const auto subtree = [&](int r) {
      double w = 0;
      for (int s = S.first[std::size_t(r)]; s <= r; ++s) w += cost[std::size_t(s)];
      return w;
    };
    for (std::size_t k = 1; k < order.size(); ++k) EXPECT_GE(subtree(order[k - 1]), subtree(order[k])) << T;
  }
}

// update_peak (schedule.h) bounds the update matrices alive in the subtree phase however the threads' claims
// interleave: the phase simulated step by step (one supernode of a randomly chosen thread per step, or of the thread
// on the latest root; a thread done with a subtree hands its root over as Handover does and claims the next in
// claim order), the bytes alive never exceed the bound.
TEST(UpdatePeak, BoundsTheSubtreePhaseForAnyInterleaving) {
  using namespace db::multifrontal;
  const Symbolic S = analyze_blocks(grid_upper(40, 40), 1, "metis");
  const std::vector<double> cost = entry_costs(S);
  const auto bytes = [&](int s) { return double(UpdateBlock::bytes(S.nrows(s) - S.ncols(s))); };
  for (int T : {2, 3, 8}) {
    const Plan plan = schedule(S, T, cost);
    const std::vector<int> order = claim_order(S, plan, cost);
    const double bound = update_peak(S, plan);
    std::vector<char> root(std::size_t(S.nsuper()), 0);
    for (int r : order) root[std::size_t(r)] = 1;
    for (unsigned seed = 1; seed <= 20; ++seed) {
      std::mt19937 random(seed);
      std::vector<char> done(std::size_t(S.nsuper()), 0), begun(std::size_t(S.nsuper()), 0);
      std::vector<int> next_child(std::size_t(S.nsuper()), 0), at(std::size_t(T), -1), in(std::size_t(T), -1);
      std::size_t claimed = 0;
      double live = 0, peak = 0;
      const auto hand_over = [&](int r) {
        const int p = S.parent[std::size_t(r)];
        if (p < 0) return;
        done[std::size_t(r)] = 1;
        for (int& k = next_child[std::size_t(p)]; S.cptr[std::size_t(p)] + k < S.cptr[std::size_t(p) + 1]; ++k) {
          const int c = S.child[std::size_t(S.cptr[std::size_t(p)] + k)];
          if (!root[std::size_t(c)]) continue;
          if (!done[std::size_t(c)]) break;
          if (!begun[std::size_t(p)]) begun[std::size_t(p)] = 1, live += bytes(p);
          live -= bytes(c);
        }
      };
      for (;;) {
        std::vector<int> busy;
        for (int t = 0; t < T; ++t) {
          if (in[std::size_t(t)] < 0 && claimed < order.size()) {
            in[std::size_t(t)] = order[claimed++];
            at[std::size_t(t)] = S.first[std::size_t(in[std::size_t(t)])];
          }
          if (in[std::size_t(t)] >= 0) busy.push_back(t);
        }
        if (busy.empty()) break;
        // Seeds past 10 favour the thread on the latest root, so that later siblings finish first and wait.
        const int t = seed <= 10 ? busy[random() % busy.size()]
                                 : *std::max_element(busy.begin(), busy.end(), [&](int a, int b) {
                                     return in[std::size_t(a)] < in[std::size_t(b)];
                                   });
        const int s = at[std::size_t(t)]++;
        live += bytes(s);
        peak = std::max(peak, live);
        for (int q = S.cptr[std::size_t(s)]; q < S.cptr[std::size_t(s) + 1]; ++q) live -= bytes(S.child[std::size_t(q)]);
        if (s == in[std::size_t(t)]) hand_over(s), in[std::size_t(t)] = -1;
      }
      EXPECT_LE(peak, bound) << "threads " << T << " seed " << seed;
    }
  }
}

// top_tree (schedule.h): every top supernode once, as a root or as a top child of its parent, children ascending,
// each subtree's cost its own plus its children's.
TEST(TopTree, EveryTopSupernodeOnceWithItsSubtreesCost) {
  using namespace db::multifrontal;
  const Symbolic S = analyze_blocks(grid_upper(60, 60), 1, "metis");
  const std::vector<double> cost = entry_costs(S);
  const Plan plan = schedule(S, 16, cost);
  ASSERT_GT(plan.top.size(), 4u);
  const TopTree tree = top_tree(S, plan, cost);
  std::vector<int> seen = tree.roots;
  for (int s : plan.top) {
    const auto& kids = tree.children[std::size_t(s)];
    EXPECT_TRUE(std::is_sorted(kids.begin(), kids.end()));
    double w = cost[std::size_t(s)];
    for (int c : kids) {
      EXPECT_EQ(S.parent[std::size_t(c)], s);
      w += tree.work[std::size_t(c)];
    }
    EXPECT_DOUBLE_EQ(tree.work[std::size_t(s)], w);
    seen.insert(seen.end(), kids.begin(), kids.end());
  }
  std::sort(seen.begin(), seen.end());
  EXPECT_EQ(seen, plan.top);
  // Siblings in the top, which the top phase runs at once.
  EXPECT_TRUE(std::any_of(plan.top.begin(), plan.top.end(),
                          [&](int s) { return tree.children[std::size_t(s)].size() > 1; }));
}

// top_shares: every subtree in one bin, at most `threads` bins, each with at least one thread. Where the bins'
// flops are worth their threads, all the threads are handed out, each bin's share within one thread of its
// proportional share; where they are not (a few thousand flops), one thread each.
TEST(TopShares, EverySubtreeOnceAndTheThreadsInProportion) {
  using namespace db::multifrontal;
  std::mt19937 rng(5);
  for (int trial = 0; trial < 300; ++trial) {
    const int k = 1 + int(rng() % 12), threads = 1 + int(rng() % 20);
    const bool small = trial % 3 == 0;
    std::vector<double> work(40, 0.0);
    std::vector<int> subtrees;
    for (int i = 0; i < k; ++i) {
      subtrees.push_back(3 * i + 1);
      work[std::size_t(3 * i + 1)] = (trial % 7 == 0 ? 1.0 : double(1 + rng() % 1000)) * (small ? 1.0 : 1e9);
    }
    const TopShares sh = top_shares(subtrees, work, threads);
    const std::size_t nb = std::min<std::size_t>(std::size_t(k), std::size_t(threads));
    ASSERT_EQ(sh.bins.size(), nb);
    ASSERT_EQ(sh.threads.size(), nb);
    std::vector<int> all;
    std::vector<double> load;
    for (const auto& bin : sh.bins) {
      EXPECT_FALSE(bin.empty());
      all.insert(all.end(), bin.begin(), bin.end());
      load.push_back(0);
      for (int r : bin) load.back() += work[std::size_t(r)];
    }
    std::sort(all.begin(), all.end());
    EXPECT_EQ(all, subtrees);
    const double total = std::accumulate(load.begin(), load.end(), 0.0);
    for (std::size_t b = 0; b < nb; ++b) {
      if (small) {
        EXPECT_EQ(sh.threads[b], 1) << trial;
        continue;
      }
      EXPECT_GE(sh.threads[b], 1);
      EXPECT_LT(std::abs(sh.threads[b] - 1 - double(threads - int(nb)) * load[b] / total), 1.0) << trial;
    }
    if (!small) {
      EXPECT_EQ(std::accumulate(sh.threads.begin(), sh.threads.end(), 0), threads) << trial;
    }
  }
}

// run_top_phase (top_phase.h): each top supernode runs once, after all its top children, and the teams of the
// fronts running at once never hold more threads than it was given; a front that fails stops its ancestors. The
// costs are scaled to flops worth many threads (threads_worth), so that the teams are not cut to one thread.
TEST(TopPhase, EachFrontOnceAfterItsChildrenWithinTheThreads) {
  using namespace db::multifrontal;
  const Symbolic S = analyze_blocks(grid_upper(60, 60), 1, "metis");
  std::vector<double> cost = entry_costs(S);
  for (double& c : cost) c *= 1e9;
  const Plan plan = schedule(S, 16, cost);
  const TopTree tree = top_tree(S, plan, cost);
  const db::SpMat A = grid_upper(4, 4);
  const auto scratch = [&] { return std::make_unique<TopScratch>(4, A, false); };
  for (int threads : {1, 2, 3, 5, 16}) {
    std::mutex m;
    std::vector<int> runs(std::size_t(S.nsuper()), 0), team_of(std::size_t(S.nsuper()), 0);
    int busy = 0, most = 0;
    bool ordered = true;
    const bool ok = run_top_phase(tree, threads, scratch, [&](int s, db::Team& team, TopScratch&) {
      {
        const std::lock_guard<std::mutex> lock(m);
        team_of[std::size_t(s)] = team.size();
        for (int c : tree.children[std::size_t(s)]) ordered = ordered && runs[std::size_t(c)] == 1;
        busy += team.size();
        most = std::max(most, busy);
      }
      volatile double x = 0;  // some work, for fronts to overlap
      for (int i = 0; i < 20000; ++i) x = x + std::sqrt(double(i));
      const std::lock_guard<std::mutex> lock(m);
      busy -= team.size();
      ++runs[std::size_t(s)];
      return true;
    });
    EXPECT_TRUE(ok);
    EXPECT_TRUE(ordered) << threads;
    EXPECT_LE(most, threads);
    for (int s = 0; s < S.nsuper(); ++s)
      EXPECT_EQ(runs[std::size_t(s)], std::binary_search(plan.top.begin(), plan.top.end(), s) ? 1 : 0) << s;
    // The teams: a bin's share of top_shares for independent subtrees, the parent's team for an only child (or
    // for all the children of a team of one).
    std::function<void(int, int)> subtree;
    const auto at_once = [&](const std::vector<int>& subtrees, int t) {
      const TopShares sh = top_shares(subtrees, tree.work, t);
      for (std::size_t b = 0; b < sh.bins.size(); ++b)
        for (int r : sh.bins[b]) subtree(r, sh.threads[b]);
    };
    subtree = [&](int s, int t) {
      EXPECT_EQ(team_of[std::size_t(s)], t) << s << " of the top on " << threads << " threads";
      const auto& kids = tree.children[std::size_t(s)];
      if (kids.size() > 1 && t > 1) return at_once(kids, t);
      for (int c : kids) subtree(c, t);
    };
    at_once(tree.roots, threads);
  }
  // A failed front: its ancestors do not run, and the phase says so.
  int failing = -1;
  for (int s : plan.top)
    if (!tree.children[std::size_t(s)].empty()) failing = tree.children[std::size_t(s)].front();
  ASSERT_GE(failing, 0);
  std::mutex m;
  std::vector<char> ran(std::size_t(S.nsuper()), 0);
  const bool ok = run_top_phase(tree, 3, scratch, [&](int s, db::Team&, TopScratch&) {
    const std::lock_guard<std::mutex> lock(m);
    ran[std::size_t(s)] = 1;
    return s != failing;
  });
  EXPECT_FALSE(ok);
  EXPECT_TRUE(ran[std::size_t(failing)]);
  for (int p = S.parent[std::size_t(failing)]; p >= 0; p = S.parent[std::size_t(p)]) EXPECT_FALSE(ran[std::size_t(p)]) << p;
}

// update_peak's top part (top_phase_peak) bounds the top phase however its independent subtrees interleave: the phase simulated
// event by event in random orders, and in orders that start every front they can first (a front's update matrix is born while its top children's live, and theirs die
// when it is done), starting from the matrices the subtree phase begun, never passes the bound. The plans' tops
// are deep (every supernode over a few others below it), so that many top matrices are not begun by subtree roots.
TEST(UpdatePeak, BoundsTheTopPhaseForAnyInterleaving) {
  using namespace db::multifrontal;
  const Symbolic S = analyze_blocks(grid_upper(60, 60), 1, "metis");
  const std::vector<double> cost = entry_costs(S);
  const auto bytes = [&](int s) { return double(UpdateBlock::bytes(S.nrows(s) - S.ncols(s))); };
  std::vector<int> below(std::size_t(S.nsuper()), 1);  // supernodes in each one's subtree
  for (int s = 0; s < S.nsuper(); ++s)
    if (const int p = S.parent[std::size_t(s)]; p >= 0) below[std::size_t(p)] += below[std::size_t(s)];
  for (int least : {3, 8, 32}) {
    Plan plan;  // the top: every supernode with `least` or more in its subtree (closed upwards); the rest, one group
    plan.subtrees.assign(1, {});
    std::vector<char> is_top(std::size_t(S.nsuper()), 0), begun(std::size_t(S.nsuper()), 0);
    for (int s = 0; s < S.nsuper(); ++s)
      if (below[std::size_t(s)] >= least) is_top[std::size_t(s)] = 1, plan.top.push_back(s);
    for (int s = 0; s < S.nsuper(); ++s)
      if (const int p = S.parent[std::size_t(s)]; !is_top[std::size_t(s)] && (p < 0 || is_top[std::size_t(p)]))
        plan.subtrees[0].push_back(s);
    const TopTree tree = top_tree(S, plan, cost);
    const double bound = top_phase_peak(S, plan);
    EXPECT_LE(bound, update_peak(S, plan));
    double early = 0;
    for (int r : plan.subtrees[0])
      if (const int p = S.parent[std::size_t(r)]; p >= 0 && !begun[std::size_t(p)]) begun[std::size_t(p)] = 1, early += bytes(p);
    double most = early;
    for (unsigned seed = 1; seed <= 30; ++seed) {
      std::mt19937 random(seed);
      std::vector<int> state(std::size_t(S.nsuper()), 0);  // 0: waiting, 1: started (own matrix born), 2: done
      double live = early;
      for (std::size_t events = 0; events < 2 * plan.top.size(); ++events) {
        std::vector<int> start, can;
        for (int s : plan.top) {
          bool kids_done = true;
          for (int c : tree.children[std::size_t(s)]) kids_done = kids_done && state[std::size_t(c)] == 2;
          if (state[std::size_t(s)] == 0 && kids_done) start.push_back(s), can.push_back(s);
          if (state[std::size_t(s)] == 1) can.push_back(s);
        }
        ASSERT_FALSE(can.empty());
        // Seeds past 15 start every front they can before any ends: the most matrices alive at once.
        const std::vector<int>& from = seed > 15 && !start.empty() ? start : can;
        const int s = from[random() % from.size()];
        if (state[std::size_t(s)]++ == 0) {
          if (!begun[std::size_t(s)]) live += bytes(s);
          most = std::max(most, live);
        } else {
          for (int c : tree.children[std::size_t(s)]) live -= bytes(c);
        }
      }
      EXPECT_LE(most, bound) << "subtrees of " << least << " seed " << seed;
    }
  }
}

// The top phase's tiles (front.h): every supernode factored with a team gives the same factor, bit for bit, on any
// team size, since the tiles depend only on the front. Natural order, two dense 600-column blocks coupled to a
// dense 300-column block but not to each other: one of them stays a supernode of its own, of three panels and a
// 300-row update matrix, so every kind of tile comes several times per front and a product's panels must be taken
// in order (with two, a fresh update matrix's two products commute).
TEST(FrontFactorization, TilesGiveTheSameFactorOnAnyTeam) {
  using namespace db::multifrontal;
  const int block = 600, tail = 300, n = 2 * block + tail;
  std::vector<Eigen::Triplet<double>> t;  // the upper triangle
  for (int j = 0; j < n; ++j) {
    t.emplace_back(j, j, 4.0 * n);
    const int last = j < 2 * block ? (j / block + 1) * block : n;  // a block's own columns, dense
    for (int i = 0; i < j; ++i)
      if (i >= last - (j < 2 * block ? block : tail) || j >= 2 * block)  // own block, or the tail's column
        t.emplace_back(i, j, std::sin(1.0 + i + 7.0 * j));
  }
  db::SpMat upper(n, n);
  upper.setFromTriplets(t.begin(), t.end());
  const Symbolic S = analyze_blocks(upper, 1, "natural");
  ASSERT_TRUE(S.perm.empty());
  int wide_with_update = 0;  // supernodes of three panels or more that form an update matrix
  for (int s = 0; s < S.nsuper(); ++s)
    wide_with_update += S.ncols(s) > 2 * FactorBlock::kWidth && S.nrows(s) > S.ncols(s);
  ASSERT_GT(wide_with_update, 0);
  const std::vector<int> counts = MatrixChunk::lower_counts(upper);
  const BlasOnOneThread one_thread;  // as in the top phase
  const auto factor_with = [&](int threads) {
    db::Team team(threads);
    std::vector<double> values(S.xptr.back(), 0.0), pivots(std::size_t(S.n), 0.0);
    FrontFactorization fronts(S, values.data(), pivots);
    Workspace ws(S.n);
    MatrixChunk chunk;
    for (int s = 0; s < S.nsuper(); ++s) {
      chunk.load(upper, counts, S, s, s);
      EXPECT_TRUE(fronts.factor_supernode(chunk, s, ws, &team)) << s;
    }
    values.insert(values.end(), pivots.begin(), pivots.end());
    return values;
  };
  const std::vector<double> one = factor_with(1);
  for (double v : one) ASSERT_TRUE(std::isfinite(v));
  for (int threads : {2, 3, 4}) EXPECT_TRUE(factor_with(threads) == one) << threads << " threads";
}
