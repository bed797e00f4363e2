#include "solvers/ordering/ring_dissection.h"

#include <algorithm>
#include <optional>
#include <memory>

#include <cholmod.h>
#include <fmt/format.h>

#include "solvers/base/error.h"
#include "solvers/base/resources.h"
#include "solvers/ordering/child_task.h"
#include "solvers/ordering/cholmod_views.h"

namespace db {
namespace {

constexpr int kNotOrdered = -1;  // where[v] of a vertex that is not ordered
constexpr int kSeparated = -2;   // where[v] of a vertex in a separator

using CommonPtr = std::unique_ptr<cholmod_common, int (*)(cholmod_common*)>;

//! A node of the dissection tree: a part of the ordered vertices; split into two children and a separator, or a
//! leaf.
struct Node {
  std::vector<int> vertices;  //!< graph vertices, ascending
  int child[2] = {-1, -1};
  std::vector<int> separator;  //!< graph vertices, ascending; ordered after both children
};

//! A local upper pattern (CSC, row < column) over a part's vertices 0 .. size - 1.
struct LocalPattern {
  std::vector<int> colptr{0}, rows;
  cholmod_sparse view() { return cholmod_upper_view(colptr.size() - 1, colptr.data(), rows.data(), nullptr); }
};

class Dissection {
 public:
  Dissection(const RingGraph& g, const RingDissection& s)
      : g_(g), settings_(s), where_(std::size_t(g.n), kNotOrdered), local_(std::size_t(g.n), -1) {}

  //! perm[new] = old over the ordered vertices' numbers.
  std::vector<int> run(int processes) {
    Node root;
    for (int v = 0; v < g_.n; ++v)
      if (g_.index[v] >= 0) root.vertices.push_back(v);
    nodes_.push_back(std::move(root));
    for (int v : nodes_[0].vertices) where_[std::size_t(v)] = 0;
    std::vector<int> perm = order_subtree(0, processes);
    for (int& v : perm) v = g_.index[v];
    return perm;
  }

 private:
  bool in_part(int v, int id) const { return where_[std::size_t(v)] == id; }

  //! The upper pattern of the 1-ring graph induced by node id's vertices; local_ numbers them.
  LocalPattern one_ring(int id) {
    const std::vector<int>& verts = nodes_[std::size_t(id)].vertices;
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
  std::vector<int> widening(int id, const std::vector<int>& part, int s) const {
    const std::vector<int>& verts = nodes_[std::size_t(id)].vertices;
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
  void thin(int id, std::vector<int>& part, int count[3]) const {
    const std::vector<int>& verts = nodes_[std::size_t(id)].vertices;
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

  //! Splits node id by a METIS separator of its 1-ring graph widened on one side; false: a leaf.
  bool split(int id) {
    const std::size_t size = nodes_[std::size_t(id)].vertices.size();
    if (size < std::size_t(std::max(settings_.leaf, 2))) return false;
    LocalPattern p = one_ring(id);
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
    const std::vector<int> w0 = widening(id, part, 0), w1 = widening(id, part, 1);
    const bool first = w0.size() != w1.size() ? w0.size() < w1.size() : count[0] >= count[1];
    for (int j : first ? w0 : w1) part[std::size_t(j)] = 2;
    count[2] += int((first ? w0 : w1).size());
    count[first ? 0 : 1] -= int((first ? w0 : w1).size());
    thin(id, part, count.data());
    Node sides[2];
    Node& node = nodes_[std::size_t(id)];
    for (std::size_t j = 0; j < size; ++j) {
      const int v = node.vertices[j];
      if (part[j] == 2) node.separator.push_back(v);
      else sides[part[j]].vertices.push_back(v);
    }
    node.vertices = {};
    for (int v : node.separator) where_[std::size_t(v)] = kSeparated;
    for (int s = 0; s < 2; ++s) {
      const int child = int(nodes_.size());
      for (int v : sides[s].vertices) where_[std::size_t(v)] = child;
      nodes_[std::size_t(id)].child[s] = child;
      nodes_.push_back(std::move(sides[s]));
    }
    return true;
  }

  //! The upper pattern of the 2-ring graph of leaf id's vertices (paths through any vertex count).
  LocalPattern two_ring(int id) {
    const std::vector<int>& verts = nodes_[std::size_t(id)].vertices;
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

  //! Leaf id's vertices in METIS's order of their 2-ring graph.
  std::vector<int> leaf_order(int id) {
    const std::vector<int>& verts = nodes_[std::size_t(id)].vertices;
    LocalPattern p = two_ring(id);
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

  //! The elimination order of node id's vertices (graph vertices): its sides' orders, then its separator; a
  //! leaf's by METIS. With `processes` > 1 the first side is ordered in a forked child process (ChildTask: METIS's
  //! random draws would interleave on threads) with half of them, while this one orders the second; the child
  //! computes what this process would, so the result does not depend on the process count. A child that fails
  //! is replaced by ordering its side here.
  std::vector<int> order_subtree(int id, int processes) {
    if (!split(id)) return nodes_[std::size_t(id)].vertices.empty() ? std::vector<int>{} : leaf_order(id);
    const int a = nodes_[std::size_t(id)].child[0], b = nodes_[std::size_t(id)].child[1];
    std::optional<ChildTask> child;
    if (processes > 1 && !nodes_[std::size_t(a)].vertices.empty())
      child.emplace(nodes_[std::size_t(a)].vertices.size(), [&] { return order_subtree(a, processes / 2); });
    std::optional<std::vector<int>> first;
    if (!child) first = order_subtree(a, 1);
    std::vector<int> second = order_subtree(b, child ? processes - processes / 2 : processes);
    if (child) first = child->result();
    if (!first) first = order_subtree(a, 1);
    first->insert(first->end(), second.begin(), second.end());
    const std::vector<int>& sep = nodes_[std::size_t(id)].separator;
    first->insert(first->end(), sep.begin(), sep.end());
    return std::move(*first);
  }

  const RingGraph& g_;
  RingDissection settings_;
  std::vector<Node> nodes_;
  std::vector<int> where_;  //!< the node holding each ordered vertex, kSeparated or kNotOrdered
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
  std::vector<int> perm = Dissection(g, settings).run(settings.processes > 0 ? settings.processes : worker_threads());
  check_permutation(perm, g.m);
  return perm;
}

}  // namespace db
