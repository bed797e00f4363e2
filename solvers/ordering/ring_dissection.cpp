#include "solvers/ordering/ring_dissection.h"

#include <algorithm>
#include <atomic>
#include <memory>

#include <cholmod.h>
#include <fmt/format.h>

#include "solvers/base/error.h"
#include "solvers/base/resources.h"
#include "solvers/ordering/cholmod_views.h"
#include "solvers/ordering/metis_random.h"
#include "solvers/ordering/suitesparse_memory.h"

namespace db {
namespace {

constexpr int kNotOrdered = -1;  // where[v] of a vertex that is not ordered
constexpr int kSeparated = -2;   // where[v] of a vertex in a separator

using CommonPtr = std::unique_ptr<cholmod_common, int (*)(cholmod_common*)>;

//! A node of the dissection tree: a part of the ordered vertices, split into two children and a separator, or a
//! leaf.
struct Node {
  int id = 0;                 //!< where_[v] of its vertices
  std::vector<int> vertices;  //!< graph vertices, ascending
};

//! A local upper pattern (CSC, row < column) over a part's vertices 0 .. size - 1.
struct LocalPattern {
  std::vector<int> colptr{0}, rows;
  cholmod_sparse view() { return cholmod_upper_view(colptr.size() - 1, colptr.data(), rows.data(), nullptr); }
};

class Dissection {
 public:
  Dissection(const RingGraph& g, const RingDissection& s)
      : g_(g), settings_(s), where_(std::size_t(g.n)), local_(std::size_t(g.n), -1) {}

  //! perm[new] = old over the ordered vertices' numbers.
  std::vector<int> run(int threads) {
    Node root{next_id_++, {}};
    for (int v = 0; v < g_.n; ++v) {
      where_[std::size_t(v)].store(g_.index[v] >= 0 ? root.id : kNotOrdered, std::memory_order_relaxed);
      if (g_.index[v] >= 0) root.vertices.push_back(v);
    }
    std::vector<int> perm = order_subtree(root, threads);
    for (int& v : perm) v = g_.index[v];
    return perm;
  }

 private:
  // Threads read where_ of vertices outside their own part (another thread's, changing meanwhile), only to see
  // that it is not their part's id: relaxed atomics make those reads defined; no id is used twice. local_ is
  // read and written only at a thread's own vertices.
  bool in_part(int v, int id) const { return where_[std::size_t(v)].load(std::memory_order_relaxed) == id; }
  void assign(const std::vector<int>& vertices, int id) {
    for (int v : vertices) where_[std::size_t(v)].store(id, std::memory_order_relaxed);
  }

  //! The upper pattern of the 1-ring graph induced by the node's vertices; local_ numbers them.
  LocalPattern one_ring(const Node& node) {
    const std::vector<int>& verts = node.vertices;
    const int id = node.id;
    for (std::size_t j = 0; j < verts.size(); ++j) local_[std::size_t(verts[j])] = int(j);
    LocalPattern p;
    for (std::size_t j = 0; j < verts.size(); ++j) {
      const std::size_t start = p.rows.size();
      const int v = verts[j];
      for (int q = g_.ptr[v]; q < g_.ptr[v + 1]; ++q)
        if (const int y = g_.adj[q]; in_part(y, id) && local_[std::size_t(y)] < int(j))
          p.rows.push_back(local_[std::size_t(y)]);
      std::sort(p.rows.begin() + std::ptrdiff_t(start), p.rows.end());
      p.colptr.push_back(int(p.rows.size()));
    }
    return p;
  }

  //! The vertices of side `s` (local numbers) that reach the separator or the other side in two steps, the
  //! latter through a vertex outside the part; part[] in local numbers: 0, 1 the sides, 2 the separator.
  std::vector<int> widening(const Node& node, const std::vector<int>& part, int s) const {
    const std::vector<int>& verts = node.vertices;
    const int id = node.id;
    std::vector<int> w;
    for (std::size_t j = 0; j < verts.size(); ++j) {
      if (part[j] != s) continue;
      const int v = verts[j];
      bool reaches = false;
      for (int q = g_.ptr[v]; q < g_.ptr[v + 1] && !reaches; ++q) {
        const int x = g_.adj[q];
        if (in_part(x, id)) {
          reaches = part[std::size_t(local_[std::size_t(x)])] == 2;
          continue;
        }
        for (int r = g_.ptr[x]; r < g_.ptr[x + 1] && !reaches; ++r)
          if (const int z = g_.adj[r]; in_part(z, id)) reaches = part[std::size_t(local_[std::size_t(z)])] == 1 - s;
      }
      if (reaches) w.push_back(int(j));
    }
    return w;
  }

  //! Moves separator vertices that reach only one side in two steps into that side (in ascending order, each
  //! move seen by the next check): what is left still separates the 2-ring graph.
  void thin(const Node& node, std::vector<int>& part, int count[3]) const {
    const std::vector<int>& verts = node.vertices;
    const int id = node.id;
    for (std::size_t j = 0; j < verts.size(); ++j) {
      if (part[j] != 2) continue;
      bool reaches[3] = {false, false, false};
      const auto see = [&](int y) {
        if (in_part(y, id)) reaches[part[std::size_t(local_[std::size_t(y)])]] = true;
      };
      const int v = verts[j];
      for (int q = g_.ptr[v]; q < g_.ptr[v + 1]; ++q) {
        const int x = g_.adj[q];
        see(x);
        for (int r = g_.ptr[x]; r < g_.ptr[x + 1]; ++r)
          if (g_.adj[r] != v) see(g_.adj[r]);
      }
      if (reaches[0] && reaches[1]) continue;
      const int side = reaches[0] ? 0 : reaches[1] ? 1 : (count[0] <= count[1] ? 0 : 1);
      part[j] = side;
      --count[2];
      ++count[side];
    }
  }

  //! Splits the node by a METIS separator of its 1-ring graph widened on one side into `sides` (new ids) and
  //! `separator` (ascending); false: a leaf.
  bool split(const Node& node, Node sides[2], std::vector<int>& separator) {
    const std::size_t size = node.vertices.size();
    if (size < std::size_t(std::max(settings_.leaf, 2))) return false;
    LocalPattern p = one_ring(node);
    cholmod_common cc;
    cholmod_start(&cc);
    const CommonPtr guard(&cc, cholmod_finish);
    cc.print = 0;
    std::vector<int> part(size);
    cholmod_sparse A = p.view();
    if (cholmod_bisect(&A, nullptr, 0, true, part.data(), &cc) < 0) return false;
    std::vector<int> count(3, 0);
    for (int k : part) ++count[std::size_t(k)];
    if (count[0] == 0 || count[1] == 0) return false;
    // Widen on the side that adds fewer vertices; on a tie, the larger side (better balance).
    const std::vector<int> w0 = widening(node, part, 0), w1 = widening(node, part, 1);
    const bool first = w0.size() != w1.size() ? w0.size() < w1.size() : count[0] >= count[1];
    for (int j : first ? w0 : w1) part[std::size_t(j)] = 2;
    count[2] += int((first ? w0 : w1).size());
    count[first ? 0 : 1] -= int((first ? w0 : w1).size());
    thin(node, part, count.data());
    for (std::size_t j = 0; j < size; ++j) {
      const int v = node.vertices[j];
      if (part[j] == 2) separator.push_back(v);
      else sides[part[j]].vertices.push_back(v);
    }
    assign(separator, kSeparated);
    for (int s = 0; s < 2; ++s) {
      sides[s].id = next_id_++;
      assign(sides[s].vertices, sides[s].id);
    }
    return true;
  }

  //! The upper pattern of the 2-ring graph of a leaf's vertices (paths through any vertex count).
  LocalPattern two_ring(const Node& node) {
    const std::vector<int>& verts = node.vertices;
    const int id = node.id;
    for (std::size_t j = 0; j < verts.size(); ++j) local_[std::size_t(verts[j])] = int(j);
    LocalPattern p;
    std::vector<int> mark(verts.size(), -1);
    for (std::size_t j = 0; j < verts.size(); ++j) {
      const std::size_t start = p.rows.size();
      const auto visit = [&](int y) {
        if (!in_part(y, id)) return;
        const int l = local_[std::size_t(y)];
        if (l >= int(j) || mark[std::size_t(l)] == int(j)) return;
        mark[std::size_t(l)] = int(j);
        p.rows.push_back(l);
      };
      const int v = verts[j];
      for (int q = g_.ptr[v]; q < g_.ptr[v + 1]; ++q) {
        const int x = g_.adj[q];
        visit(x);
        for (int r = g_.ptr[x]; r < g_.ptr[x + 1]; ++r) visit(g_.adj[r]);
      }
      std::sort(p.rows.begin() + std::ptrdiff_t(start), p.rows.end());
      p.colptr.push_back(int(p.rows.size()));
    }
    return p;
  }

  //! A leaf's vertices in METIS's order of their 2-ring graph.
  std::vector<int> leaf_order(const Node& node) {
    const std::vector<int>& verts = node.vertices;
    LocalPattern p = two_ring(node);
    cholmod_common cc;
    cholmod_start(&cc);
    const CommonPtr guard(&cc, cholmod_finish);
    cc.print = 0;
    std::vector<int> perm(verts.size());
    cholmod_sparse A = p.view();
    if (!cholmod_metis(&A, nullptr, 0, false, perm.data(), &cc))
      throw SolverError(fmt::format("METIS failed on a {}-vertex part of the ring dissection, CHOLMOD status {}",
                                    verts.size(), cc.status));
    for (int& k : perm) k = verts[std::size_t(k)];
    return perm;
  }

  //! The elimination order of the node's vertices (graph vertices): its sides' orders, then its separator; a
  //! leaf's by METIS. With `threads` > 1 (and METIS able to run on threads, metis_random.h) the two sides are ordered
  //! at once, each with half of them; every side computes what it would alone, so the result does not depend on
  //! the thread count.
  std::vector<int> order_subtree(const Node& node, int threads) {
    Node child[2];
    std::vector<int> sep;
    if (!split(node, child, sep)) return node.vertices.empty() ? std::vector<int>{} : leaf_order(node);
    std::vector<int> order[2];
    const int share[2] = {threads / 2, threads - threads / 2};
    const auto order_side = [&](int s) { order[s] = order_subtree(child[s], std::max(share[s], 1)); };
    if (threads > 1 && metis_on_threads()) {
      run_tasks(2, order_side);
    } else {
      order_side(0);
      order_side(1);
    }
    std::vector<int>& out = order[0];
    out.insert(out.end(), order[1].begin(), order[1].end());
    out.insert(out.end(), sep.begin(), sep.end());
    return std::move(out);
  }

  const RingGraph& g_;
  RingDissection settings_;
  std::atomic<int> next_id_{0};
  std::vector<std::atomic<int>> where_;  //!< the node holding each ordered vertex, kSeparated or kNotOrdered
  std::vector<int> local_;  //!< each vertex's number within the part being split or ordered
};

//! Checks that perm is a permutation of 0 .. m - 1.
void check_permutation(const std::vector<int>& perm, int m) {
  std::vector<char> seen(std::size_t(m), 0);
  for (int v : perm)
    if (v < 0 || v >= m || seen[std::size_t(v)]++)
      throw SolverError("ring dissection: the ordering is not a permutation");
  if (int(perm.size()) != m) throw SolverError("ring dissection: the ordering is incomplete");
}

}  // namespace

std::vector<int> ring_dissection_order(const RingGraph& g, const RingDissection& settings) {
  if (g.m == 0) return {};
  use_huge_pages_in_suitesparse();
  std::vector<int> perm = Dissection(g, settings).run(settings.threads > 0 ? settings.threads : worker_threads());
  check_permutation(perm, g.m);
  return perm;
}

}  // namespace db
