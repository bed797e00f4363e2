#include "solvers/ordering/dissection_postorder.h"

#include <algorithm>
#include <cstddef>
#include <memory>
#include <numeric>
#include <utility>

#include <cholmod.h>
#include <fmt/format.h>

#include "solvers/base/error.h"
#include "solvers/base/resources.h"
#include "solvers/ordering/cholmod_views.h"

namespace db {
namespace {

//! An upper-triangular pattern with its diagonal in CSC (rows of a column in any order), built column by column.
struct UpperPattern {
  std::vector<int> colptr{0}, rows;
  int size() const { return int(colptr.size()) - 1; }
  void close_column() {
    rows.push_back(size());  // the diagonal
    colptr.push_back(int(rows.size()));
  }
};

//! CHOLMOD's cholmod_common, started and finished with its owner.
struct Common {
  cholmod_common cc;
  Common() {
    cholmod_start(&cc);
    cc.print = 0;
  }
  ~Common() { cholmod_finish(&cc); }
  Common(const Common&) = delete;
  Common& operator=(const Common&) = delete;
};

//! CHOLMOD's elimination tree (parent -1 at a root) and column counts of L for `a` in its own order.
void tree_and_counts(UpperPattern& a, int* parent, int* count, cholmod_common& cc) {
  const int n = a.size();
  if (n == 0) return;
  cholmod_sparse A = cholmod_upper_view(std::size_t(n), a.colptr.data(), a.rows.data(), nullptr);
  A.sorted = 0;
  const auto size = static_cast<std::size_t>(n);
  std::vector<int> natural(size), post(size), first(size), level(size);
  std::iota(natural.begin(), natural.end(), 0);
  if (!cholmod_analyze_ordering(&A, CHOLMOD_NATURAL, natural.data(), nullptr, 0, parent, post.data(), count,
                                first.data(), level.data(), &cc))
    throw SolverError(fmt::format("postorder of a dissection: CHOLMOD's analysis of {} vertices failed, status {}",
                                  n, cc.status));
}

//! What the analysis of the parts hands to that of the separators.
struct Dissection {
  const GraphPattern& adjacency;
  const std::vector<int>& order;
  std::vector<int> position;  //!< position of each vertex in order
  std::vector<int> part_of;   //!< part of each position; -1 for a separator vertex
  std::vector<int> parent, count;  //!< by position: the elimination tree (positions) and column counts
};

//! The pattern of part `p` (positions r.lo .. r.hi - 1, numbered from 0) followed by its halo, the separator
//! vertices it touches (ascending positions into `halo`), and each edge out of the part as (separator position,
//! part column) into `out`, sorted. \throw SolverError on an edge to another part or to an earlier position.
UpperPattern part_with_halo(const Dissection& d, int p, PositionRange r, std::vector<std::pair<int, int>>& out,
                            std::vector<int>& halo) {
  UpperPattern a;
  for (int j = r.lo; j < r.hi; ++j) {
    const int v = d.order[std::size_t(j)];
    for (int q = d.adjacency.colptr[v]; q < d.adjacency.colptr[v + 1]; ++q) {
      const int i = d.position[std::size_t(d.adjacency.rows[q])];
      if (d.part_of[std::size_t(i)] == p) {
        if (i < j) a.rows.push_back(i - r.lo);
      } else if (d.part_of[std::size_t(i)] >= 0 || i < r.hi) {
        throw SolverError(fmt::format("postorder of a dissection: an edge from part {} leads to position {}, which "
                                      "is not a later separator vertex", p, i));
      } else {
        out.emplace_back(i, j - r.lo);
      }
    }
    a.close_column();
  }
  std::sort(out.begin(), out.end());
  for (std::size_t e = 0; e < out.size(); ++e) {
    a.rows.push_back(out[e].second);
    if (e + 1 == out.size() || out[e + 1].first != out[e].first) {
      halo.push_back(out[e].first);
      a.close_column();
    }
  }
  return a;
}

//! The tree and counts of part `p` (positions r.lo .. r.hi - 1) into d.parent and d.count, and the separators'
//! graph's star edges (hub, separator vertex) of each of its connected pieces into `stars`. The part is analyzed
//! with its halo after it: the halo's rows of L are the part's columns' only rows outside it, and paths through the
//! part's earlier vertices are all that make them.
void analyze_part(Dissection& d, int p, PositionRange r, std::vector<std::pair<int, int>>& stars, cholmod_common& cc) {
  const int m = r.hi - r.lo;
  std::vector<std::pair<int, int>> out;
  std::vector<int> halo;
  UpperPattern a = part_with_halo(d, p, r, out, halo);
  std::vector<int> parent(std::size_t(a.size())), count(std::size_t(a.size()));
  tree_and_counts(a, parent.data(), count.data(), cc);
  // The pieces: each part vertex's root in the part's forest; a root's parent is its piece's first halo vertex.
  std::vector<int> root(static_cast<std::size_t>(m));
  for (int k = m - 1; k >= 0; --k) {
    const int up = parent[std::size_t(k)];
    root[std::size_t(k)] = up < 0 || up >= m ? k : root[std::size_t(up)];
    d.parent[std::size_t(r.lo + k)] = up < 0 ? -1 : up < m ? r.lo + up : halo[std::size_t(up - m)];
    d.count[std::size_t(r.lo + k)] = count[std::size_t(k)];
  }
  std::vector<std::pair<int, int>> touched;  // (piece's root, separator position)
  for (const auto& [i, k] : out) touched.emplace_back(root[std::size_t(k)], i);
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
  for (std::size_t t = 0, hub = 0; t < touched.size(); ++t) {
    if (t == 0 || touched[t].first != touched[t - 1].first) hub = t;  // the piece's first separator vertex
    else stars.emplace_back(touched[hub].second, touched[t].second);
  }
}

//! The tree and counts of the separator vertices into d.parent and d.count, from CHOLMOD's analysis of their graph:
//! their edges among themselves and the parts' star edges.
void analyze_separators(Dissection& d, std::vector<std::pair<int, int>>& stars, cholmod_common& cc) {
  const int n = int(d.order.size());
  std::vector<int> separator, local(std::size_t(n), -1);
  for (int i = 0; i < n; ++i)
    if (d.part_of[std::size_t(i)] < 0) {
      local[std::size_t(i)] = int(separator.size());
      separator.push_back(i);
    }
  if (separator.empty()) return;
  std::sort(stars.begin(), stars.end(), [](const auto& x, const auto& y) { return x.second < y.second; });
  UpperPattern a;
  auto star = stars.begin();
  for (const int j : separator) {
    const int v = d.order[std::size_t(j)];
    for (int q = d.adjacency.colptr[v]; q < d.adjacency.colptr[v + 1]; ++q)
      if (const int i = d.position[std::size_t(d.adjacency.rows[q])]; i < j && local[std::size_t(i)] >= 0)
        a.rows.push_back(local[std::size_t(i)]);
    for (; star != stars.end() && star->second == j; ++star) a.rows.push_back(local[std::size_t(star->first)]);
    // A star edge may repeat an edge of the graph or another piece's star.
    const auto column = a.rows.begin() + a.colptr.back();
    std::sort(column, a.rows.end());
    a.rows.erase(std::unique(column, a.rows.end()), a.rows.end());
    a.close_column();
  }
  std::vector<int> parent(separator.size()), count(separator.size());
  tree_and_counts(a, parent.data(), count.data(), cc);
  for (std::size_t k = 0; k < separator.size(); ++k) {
    const int up = parent[k];
    d.parent[std::size_t(separator[k])] = up < 0 ? -1 : separator[std::size_t(up)];
    d.count[std::size_t(separator[k])] = count[k];
  }
}

//! d.position and d.part_of. \throw SolverError unless d.order is a permutation and `parts` disjoint ranges of it.
void locate(Dissection& d, const std::vector<PositionRange>& parts) {
  const int n = int(d.order.size());
  for (int k = 0; k < n; ++k) {
    const int v = d.order[std::size_t(k)];
    if (v < 0 || v >= n || d.position[std::size_t(v)] >= 0)
      throw SolverError("postorder of a dissection: the order is not a permutation");
    d.position[std::size_t(v)] = k;
  }
  for (std::size_t p = 0; p < parts.size(); ++p) {
    const PositionRange r = parts[p];
    if (r.lo < 0 || r.lo > r.hi || r.hi > n)
      throw SolverError(fmt::format("postorder of a dissection: part [{}, {}) outside {} positions", r.lo, r.hi, n));
    for (int k = r.lo; k < r.hi; ++k) {
      if (d.part_of[std::size_t(k)] >= 0) throw SolverError("postorder of a dissection: the parts overlap");
      d.part_of[std::size_t(k)] = int(p);
    }
  }
}

//! The tree and counts of `d` in the postorder `post` (post[new] = old position), as CHOLMOD relabels its own after
//! postordering them; the graph's upper entries from its adjacency lists (each edge listed both ways).
void relabel(const Dissection& d, const std::vector<int>& post, EliminationTree& tree) {
  const std::size_t n = post.size();
  std::vector<int> at(n);
  for (std::size_t k = 0; k < n; ++k) at[std::size_t(post[k])] = int(k);
  tree.parent.resize(n);
  tree.count.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const int up = d.parent[std::size_t(post[k])];
    tree.parent[k] = up < 0 ? -1 : at[std::size_t(up)];
    tree.count[k] = d.count[std::size_t(post[k])];
  }
  tree.upper_entries = std::size_t(d.adjacency.colptr[d.adjacency.n]) / 2 + n;
}

}  // namespace

std::vector<int> postorder_dissection(const GraphPattern& adjacency, const std::vector<int>& order,
                                      const std::vector<PositionRange>& parts, int threads, EliminationTree* tree) {
  const int n = adjacency.n;
  if (int(order.size()) != n)
    throw SolverError(
        fmt::format("postorder of a dissection: an order of {} entries for {} vertices", order.size(), n));
  Dissection d{adjacency, order, std::vector<int>(std::size_t(n), -1), std::vector<int>(std::size_t(n), -1),
               std::vector<int>(std::size_t(n)), std::vector<int>(std::size_t(n))};
  locate(d, parts);
  const int np = int(parts.size());
  std::vector<std::vector<std::pair<int, int>>> stars(static_cast<std::size_t>(np));
  const int tasks = std::max(1, std::min(threads, np));
  run_tasks(tasks, [&](int t) {
    Common c;
    for (int p = t; p < np; p += tasks) analyze_part(d, p, parts[std::size_t(p)], stars[std::size_t(p)], c.cc);
  });
  std::vector<std::pair<int, int>> all;  // in part order: the same for any thread count
  for (const auto& s : stars) all.insert(all.end(), s.begin(), s.end());
  Common c;
  analyze_separators(d, all, c.cc);
  std::vector<int> post(static_cast<std::size_t>(n));
  if (n > 0 && cholmod_postorder(d.parent.data(), std::size_t(n), d.count.data(), post.data(), &c.cc) != n)
    throw SolverError(fmt::format("postorder of a dissection: CHOLMOD's postorder failed, status {}", c.cc.status));
  std::vector<int> result(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) result[std::size_t(k)] = order[std::size_t(post[std::size_t(k)])];
  if (tree) relabel(d, post, *tree);
  return result;
}

}  // namespace db
