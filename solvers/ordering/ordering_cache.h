#pragma once
//! An opt-in cache of fill-reducing orderings on disk. An ordering depends only on the graph and the method, so
//! runs on the same connectivity and region of interest (another handle transform, other weights, another
//! frame count) can skip METIS, most of the analysis phase. On when the environment variable
//! DEFORMBENCH_ORDERING_CACHE names a directory, off otherwise (the measurements of the thesis tables are cold).
//! A cached permutation is used only after it is checked to be a permutation of the graph's size; any
//! permutation gives a correct factorization, so a stale or colliding entry could cost fill, never correctness.
#include <string>
#include <vector>

#include "solvers/ordering/graph_ordering.h"

namespace db {

class OrderingCache {
 public:
  //! The cache DEFORMBENCH_ORDERING_CACHE names; disabled when it is unset or empty.
  static OrderingCache from_environment();
  //! A cache in directory `dir`; disabled when `dir` is empty.
  explicit OrderingCache(std::string dir) : dir_(std::move(dir)) {}

  bool enabled() const { return !dir_.empty(); }
  //! The file holding the ordering of `g` under `method`: DIR/METHOD-N-HASH.perm, HASH a 64-bit FNV-1a of the
  //! pattern's arrays.
  std::string path(const GraphPattern& g, const std::string& method) const;
  //! The cached permutation (perm[new] = old), or empty: not cached, unreadable or not a permutation of g.n.
  std::vector<int> find(const GraphPattern& g, const std::string& method) const;
  //! Writes `perm` (g.n entries), atomically. \throw Error when the directory cannot be written.
  void store(const GraphPattern& g, const std::string& method, const int* perm) const;

 private:
  std::string dir_;
};

}  // namespace db
