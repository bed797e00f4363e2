// The opt-in ordering cache (solvers/ordering/ordering_cache.h): what it stores is what an uncached analysis
// computes, a hit gives the same analysis (or order_graph's permutation), and a damaged entry is recomputed, not
// used.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <cholmod.h>
#include <gtest/gtest.h>

#include "solvers/base/error.h"
#include "solvers/tests/worker_threads.h"
#include "solvers/ordering/graph_ordering.h"
#include "solvers/ordering/ordering_cache.h"

namespace {

namespace fs = std::filesystem;

//! Upper triangle (with the diagonal) of a k x k grid's 9-point stencil: a graph METIS dissects.
struct Grid {
  std::vector<int> colptr{0}, rows;
  explicit Grid(int k) {
    for (int j = 0; j < k * k; ++j) {
      const int x = j % k, y = j / k;
      for (int i = 0; i <= j; ++i)
        if (std::abs(i % k - x) <= 1 && std::abs(i / k - y) <= 1) rows.push_back(i);
      colptr.push_back(int(rows.size()));
    }
  }
  db::GraphPattern pattern() const { return {int(colptr.size()) - 1, colptr.data(), rows.data()}; }
};

//! A fresh directory, removed with it; DEFORMBENCH_ORDERING_CACHE names it meanwhile.
struct CacheDir {
  fs::path dir;
  CacheDir() {
    std::string t = (fs::temp_directory_path() / "deformbench-ordering-cache-XXXXXX").string();
    dir = ::mkdtemp(t.data());
    ::setenv("DEFORMBENCH_ORDERING_CACHE", dir.c_str(), 1);
  }
  ~CacheDir() {
    ::unsetenv("DEFORMBENCH_ORDERING_CACHE");
    fs::remove_all(dir);
  }
};

//! The permutation and nnz(L) of analyze_graph under `method` (simplicial).
struct Analysis {
  std::vector<int> perm;
  double lnz = 0;
};
Analysis analyze(const db::GraphPattern& g, const std::string& method) {
  cholmod_common cc;
  cholmod_start(&cc);
  cc.print = 0;
  cc.supernodal = CHOLMOD_SIMPLICIAL;
  cholmod_factor* L = db::analyze_graph(g, method, cc);
  Analysis a;
  const int* p = static_cast<const int*>(L->Perm);
  a.perm.assign(p, p + g.n);
  a.lnz = cc.lnz;
  cholmod_free_factor(&L, &cc);
  cholmod_finish(&cc);
  return a;
}

TEST(OrderingCache, StoresWhatTheAnalysisComputesAndHitsGiveTheSameAnalysis) {
  const Grid grid(40);
  const db::GraphPattern g = grid.pattern();
  const Analysis cold = analyze(g, "metis");  // no cache: the variable is unset
  CacheDir tmp;
  const db::OrderingCache cache = db::OrderingCache::from_environment();
  ASSERT_TRUE(cache.enabled());
  EXPECT_TRUE(cache.find(g, "metis").empty());
  const Analysis first = analyze(g, "metis");  // a miss: computed and stored
  EXPECT_EQ(first.perm, cold.perm);
  EXPECT_EQ(cache.find(g, "metis"), cold.perm);
  const Analysis hit = analyze(g, "metis");
  EXPECT_EQ(hit.perm, cold.perm);
  EXPECT_EQ(hit.lnz, cold.lnz);
  // Keyed by method and pattern: neither AMD nor a changed graph finds METIS's entry.
  EXPECT_TRUE(cache.find(g, "amd").empty());
  const Grid other(39);
  EXPECT_TRUE(cache.find(other.pattern(), "metis").empty());
  EXPECT_FALSE(fs::exists(cache.path(g, "natural")));
  analyze(g, "natural");  // nothing to cache
  EXPECT_FALSE(fs::exists(cache.path(g, "natural")));
}

// A dissected METIS ordering (20000 vertices or more) depends on its levels, one more per doubling of the threads
// beyond two: each level count has its own entry, so a warm run gives what a cold run on its thread count gives.
TEST(OrderingCache, DissectedOrderingsAreCachedPerLevelCount) {
  const Grid grid(150);
  const db::GraphPattern g = grid.pattern();
  CacheDir tmp;
  const db::OrderingCache cache = db::OrderingCache::from_environment();
  const auto analyze_on = [&](int threads) {
    const db::test::WorkerThreads scope(threads);
    return analyze(g, "metis");
  };
  const Analysis four = analyze_on(4);
  EXPECT_TRUE(cache.find(g, "metis").empty());
  const Analysis two = analyze_on(2);
  EXPECT_EQ(cache.find(g, "metis2-even"), four.perm);
  EXPECT_EQ(cache.find(g, "metis"), two.perm);
  EXPECT_NE(two.perm, four.perm);
}

// order_graph (the permutation alone, a dissected one postordered part by part) shares analyze_graph's entries.
TEST(OrderingCache, OrderGraphStoresAndFindsTheSameEntries) {
  const db::test::WorkerThreads two(2);  // the entry "metis": one level of splits (more threads, more levels)
  const Grid grid(150);  // dissected
  const db::GraphPattern g = grid.pattern();
  const Analysis cold = analyze(g, "metis");
  CacheDir tmp;
  const db::OrderingCache cache = db::OrderingCache::from_environment();
  EXPECT_EQ(db::order_graph(g, "metis"), cold.perm);  // a miss: computed and stored
  EXPECT_EQ(cache.find(g, "metis"), cold.perm);
  std::vector<int> planted(cold.perm.rbegin(), cold.perm.rend());
  cache.store(g, "metis", planted.data());
  EXPECT_EQ(db::order_graph(g, "metis"), planted);  // a hit: the entry as it is
}

TEST(OrderingCache, DamagedEntriesAreRecomputed) {
  const Grid grid(30);
  const db::GraphPattern g = grid.pattern();
  CacheDir tmp;
  const db::OrderingCache cache = db::OrderingCache::from_environment();
  const Analysis cold = analyze(g, "amd");
  std::vector<int> bad = cold.perm;
  bad[0] = bad[1];  // not a permutation
  cache.store(g, "amd", bad.data());
  EXPECT_TRUE(cache.find(g, "amd").empty());
  EXPECT_EQ(analyze(g, "amd").perm, cold.perm);  // recomputed, and stored again
  EXPECT_EQ(cache.find(g, "amd"), cold.perm);
  fs::resize_file(cache.path(g, "amd"), fs::file_size(cache.path(g, "amd")) - 4);  // truncated
  EXPECT_TRUE(cache.find(g, "amd").empty());
  EXPECT_EQ(analyze(g, "amd").perm, cold.perm);
}

TEST(OrderingCache, AnUnwritableDirectoryIsAnErrorNamingTheVariable) {
  const Grid grid(10);
  const db::OrderingCache cache("/nonexistent/deformbench-cache");
  const std::vector<int> perm = analyze(grid.pattern(), "amd").perm;
  try {
    cache.store(grid.pattern(), "amd", perm.data());
    FAIL() << "no error";
  } catch (const db::Error& e) {
    EXPECT_NE(std::string(e.what()).find("DEFORMBENCH_ORDERING_CACHE"), std::string::npos) << e.what();
  }
}

}  // namespace
