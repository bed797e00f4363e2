#include "solvers/ordering/adjacency_lists.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "solvers/base/resources.h"

namespace db {

int adjacency_ranges(long entries) {
  constexpr long kGrain = 1L << 18;
  return int(std::clamp<long>(std::min<long>(worker_threads(), entries / kGrain + 1), 1, 8));
}

AdjacencyLists adjacency_lists(const GraphPattern& g, int ranges) {
  const int n = g.n;
  const int T = std::max(1, std::min(ranges, std::max(n, 1)));
  const std::vector<int> at = balanced_columns(g.colptr, 0, n, T);
  // below[t][r]: entries (r, j), r < j, of range t's columns j: r's list entries from that range. own[j]: column
  // j's entries above the diagonal, the first entries of j's list.
  std::vector<std::vector<int>> below(static_cast<std::size_t>(T));
  std::vector<int> own(static_cast<std::size_t>(n), 0);
  run_tasks(T, [&](int t) {
    std::vector<int>& count = below[std::size_t(t)];
    count.assign(std::size_t(n), 0);
    for (int j = at[std::size_t(t)]; j < at[std::size_t(t) + 1]; ++j)
      for (int q = g.colptr[j]; q < g.colptr[j + 1]; ++q)
        if (const int r = g.rows[q]; r < j) ++count[std::size_t(r)], ++own[std::size_t(j)];
  });
  AdjacencyLists h;
  h.xadj.assign(std::size_t(n) + 1, 0);
  for (int v = 0; v < n; ++v) {
    int degree = own[std::size_t(v)];
    for (const std::vector<int>& count : below) degree += count[std::size_t(v)];
    h.xadj[std::size_t(v) + 1] = h.xadj[std::size_t(v)] + degree;
  }
  h.adjncy.resize(std::size_t(h.xadj.back()));
  // Each list: its own column's rows, then the later columns that hold it, range by range: ascending throughout.
  // below[t][v] becomes the first slot of range t's entries in v's list.
  run_tasks(T, [&](int t) {
    const int lo = int(std::int64_t(n) * t / T), hi = int(std::int64_t(n) * (t + 1) / T);
    for (int v = lo; v < hi; ++v) {
      int next = h.xadj[std::size_t(v)] + own[std::size_t(v)];
      for (std::vector<int>& count : below) {
        const int c = count[std::size_t(v)];
        count[std::size_t(v)] = next;
        next += c;
      }
    }
  });
  run_tasks(T, [&](int t) {
    std::vector<int>& slot = below[std::size_t(t)];
    for (int j = at[std::size_t(t)]; j < at[std::size_t(t) + 1]; ++j) {
      int mine = h.xadj[std::size_t(j)];
      for (int q = g.colptr[j]; q < g.colptr[j + 1]; ++q)
        if (const int r = g.rows[q]; r < j) {
          h.adjncy[std::size_t(mine++)] = r;
          h.adjncy[std::size_t(slot[std::size_t(r)]++)] = j;
        }
    }
  });
  return h;
}

}  // namespace db
