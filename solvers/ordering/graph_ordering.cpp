#include "solvers/ordering/graph_ordering.h"

#include <algorithm>
#include <atomic>
#include <memory>
#include <vector>

#include <fmt/format.h>
#include <metis.h>

#include "solvers/base/error.h"
#include "solvers/base/resources.h"
#include "solvers/ordering/adjacency_lists.h"
#include "solvers/ordering/cholmod_views.h"
#include "solvers/ordering/dissection_postorder.h"
#include "solvers/ordering/metis_random.h"
#include "solvers/ordering/ordering_cache.h"
#include "solvers/ordering/suitesparse_memory.h"

namespace db {
namespace {

static_assert(sizeof(idx_t) == sizeof(int), "METIS built with 32-bit indices (Debian's), as CHOLMOD's int interface");

//! Full adjacency lists as METIS reads them: each edge both ways, no self loops, ascending (idx_t is int).
using Adjacency = AdjacencyLists;

//! A graph as METIS reads it and the index of each of its vertices in the graph it was taken from; optionally a
//! guide: a sparser graph on the same vertices whose separators, widened, separate this one (the 1-ring graph
//! of a 2-ring pattern; empty when there is none).
struct MetisGraph : Adjacency {
  Adjacency guide;
  std::vector<int> vertices;
  idx_t size() const { return idx_t(vertices.size()); }
  bool guided() const { return guide.xadj.size() > 1; }
};

//! The adjacency lists of g (its upper triangle read; the diagonal dropped): what cholmod_metis hands METIS; on the
//! worker threads where the graph is large.
Adjacency full_adjacency(const GraphPattern& g) { return adjacency_lists(g, adjacency_ranges(g.colptr[g.n])); }

//! The METIS graph of g, guided by `guide` when it is given (a graph on the same vertices).
MetisGraph full_graph(const GraphPattern& g, const GraphPattern* guide = nullptr) {
  MetisGraph h;
  static_cast<Adjacency&>(h) = full_adjacency(g);
  if (guide) h.guide = full_adjacency(*guide);
  h.vertices.resize(std::size_t(g.n));
  for (int v = 0; v < g.n; ++v) h.vertices[std::size_t(v)] = v;
  return h;
}

//! The lists of a's vertices v with local[v] >= 0, renumbered by local, the edges to others dropped.
Adjacency induced_lists(const Adjacency& a, const std::vector<idx_t>& local, std::size_t size) {
  Adjacency h;
  h.xadj.reserve(size + 1);
  for (std::size_t v = 0; v < local.size(); ++v) {
    if (local[v] < 0) continue;
    for (idx_t q = a.xadj[v]; q < a.xadj[v + 1]; ++q)
      if (const idx_t r = local[std::size_t(a.adjncy[std::size_t(q)])]; r >= 0) h.adjncy.push_back(r);
    h.xadj.push_back(idx_t(h.adjncy.size()));
  }
  return h;
}

//! The subgraph of g (and of its guide) induced by its vertices v with part[v] == which, renumbered in ascending
//! order.
MetisGraph induced(const MetisGraph& g, const std::vector<idx_t>& part, idx_t which) {
  MetisGraph h;
  std::vector<idx_t> local(std::size_t(g.size()), -1);
  for (idx_t v = 0; v < g.size(); ++v)
    if (part[std::size_t(v)] == which) {
      local[std::size_t(v)] = h.size();
      h.vertices.push_back(g.vertices[std::size_t(v)]);
    }
  static_cast<Adjacency&>(h) = induced_lists(g, local, h.vertices.size());
  if (g.guided()) h.guide = induced_lists(g.guide, local, h.vertices.size());
  return h;
}

//! METIS nested dissection (METIS_NodeND, default options: the ordering cholmod_metis computes) of h, as its
//! vertices' graph indices in elimination order. Unpostordered: the analysis of the whole graph postorders at
//! the end.
std::vector<int> metis_order(MetisGraph& h) {
  idx_t n = h.size();
  if (n == 0) return {};
  std::vector<idx_t> perm(static_cast<std::size_t>(n)), iperm(static_cast<std::size_t>(n));
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  if (const int status = METIS_NodeND(&n, h.xadj.data(), h.adjncy.data(), nullptr, options, perm.data(), iperm.data());
      status != METIS_OK)
    throw SolverError(fmt::format("METIS ordering failed on {} vertices, METIS status {}", n, status));
  std::vector<int> order(static_cast<std::size_t>(n));
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = h.vertices[std::size_t(perm[k])];
  return order;
}

// The first split's imbalance bound (METIS's ufactor, in thousandths): METIS_NodeND's own (200: sides up to 1.2x
// half) can leave one thread ordering 60% of the graph while the other waits; a nearly even split (1.02x)
// shortens the longer of the two orderings that run at once, and on the armadillo edits its fill is no larger
// (results/records/2026-11-26-analysis-levers). The deeper splits (with more than two threads) keep METIS's own
// bound: a tight one at every level cost several percent of nnz(L) at four levels on the armadillo patterns
// (results/records/2026-11-26-ordering-threads/tuning, `depth` mode).
constexpr idx_t kSplitUfactor = 20;
// METIS's own imbalance bound for nested dissection (its OMETIS default), which the deeper splits keep.
constexpr idx_t kMetisUfactor = 200;
// Below the first level, parts of fewer vertices are ordered whole: METIS takes a few tens of milliseconds on them.
constexpr idx_t kSplitVertices = 10000;
// Parts of fewer vertices are not split to even out the parts (split_rule): their ordering is short beside the
// splits' chain.
constexpr idx_t kEvenVertices = kSplitVertices / 2;

// The balance bound of the refinement that follows a guided split (METIS_NodeRefine's ubfactor): no tighter than
// 1.05, so that the refinement can move vertices after the widening has unbalanced the sides a little.
constexpr double kRefineBalance = 1.05;

//! Widens a separator of h's guide into one of h: the vertices of one side with a neighbour on the other side in
//! h join the separator, on the side where they are fewer (on a tie, the larger side).
void widen(const MetisGraph& h, std::vector<idx_t>& part) {
  std::vector<idx_t> reach[2];
  for (idx_t v = 0; v < h.size(); ++v) {
    const idx_t s = part[std::size_t(v)];
    if (s == 2) continue;
    for (idx_t q = h.xadj[std::size_t(v)]; q < h.xadj[std::size_t(v) + 1]; ++q)
      if (part[std::size_t(h.adjncy[std::size_t(q)])] == 1 - s) {
        reach[s].push_back(v);
        break;
      }
  }
  const auto count = [&](idx_t s) { return std::count(part.begin(), part.end(), s); };
  const int side = reach[0].size() != reach[1].size() ? (reach[0].size() < reach[1].size() ? 0 : 1)
                                                       : (count(0) >= count(1) ? 0 : 1);
  for (idx_t v : reach[side]) part[std::size_t(v)] = 2;
}

//! METIS's vertex separator of h: part[v] 0 or 1 (the sides) or 2 (the separator); `ufactor` 0: METIS's own
//! balance. A guided graph is split on its guide, the separator widened to separate h and refined on h by
//! METIS's FM refinement (results/records/2026-11-27-guided-splits: the guide's split costs less, the fill is
//! the same over METIS's random draws). False when METIS fails or leaves a side empty.
bool bisect(MetisGraph& h, idx_t ufactor, std::vector<idx_t>& part) {
  idx_t n = h.size(), separator = 0;
  part.assign(std::size_t(n), 0);
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  if (ufactor > 0) options[METIS_OPTION_UFACTOR] = ufactor;
  Adjacency& cut = h.guided() ? h.guide : h;
  if (METIS_ComputeVertexSeparator(&n, cut.xadj.data(), cut.adjncy.data(), nullptr, options, &separator,
                                   part.data()) != METIS_OK)
    return false;
  if (h.guided()) {
    widen(h, part);
    const double balance = std::max(kRefineBalance, 1 + double(ufactor > 0 ? ufactor : kMetisUfactor) / 1000);
    std::vector<idx_t> marker(std::size_t(n), -1);
    if (METIS_NodeRefine(n, h.xadj.data(), nullptr, h.adjncy.data(), part.data(), marker.data(), real_t(balance)) !=
        METIS_OK)
      return false;
  }
  const auto side = [&](idx_t s) { return std::count(part.begin(), part.end(), s); };
  return side(0) > 0 && side(1) > 0;
}

//! A dissected order (graph indices in elimination order) and the ranges of its parts, those METIS_NodeND ordered.
struct Dissected {
  std::vector<int> order;
  std::vector<PositionRange> parts;
};

//! The splits of a dissection: a node is a part to order (its graph, then its order) or a split (its two sides, in
//! elimination order, and its separator, ordered after them).
struct SplitNode {
  MetisGraph graph;
  std::vector<int> order;
  std::unique_ptr<SplitNode> side[2];
  std::vector<int> separator;
  bool is_part() const { return !side[0]; }
};

//! When a node of a dissection is split: while `levels` remain (splits still to make above the parts), if it has
//! kSplitVertices or more; at any level, if it has more than `oversize` (0: no bound), so that the parts the threads
//! order are evener.
struct SplitRule {
  int levels;
  idx_t ufactor, oversize;
  SplitRule below() const { return {levels - 1, 0, oversize}; }
  bool splits(idx_t n) const { return (levels > 0 && n >= kSplitVertices) || (oversize > 0 && n > oversize); }
};

//! Splits h by `rule` (METIS vertex separators; the first at `rule.ufactor`, the deeper at METIS's own balance)
//! into the tree of its parts, unordered. With `threads` > 1 (and METIS able to run on threads, metis_random.h) the
//! two sides of a split are split at once, each with a share of the threads; the tree does not depend on `threads`.
//! h is moved into the tree or released once split, unless `keep` (then a part is a copy).
std::unique_ptr<SplitNode> split_tree(MetisGraph& h, SplitRule rule, int threads, bool keep = false) {
  auto node = std::make_unique<SplitNode>();
  std::vector<idx_t> part;
  if (!rule.splits(h.size()) || !bisect(h, rule.ufactor, part)) {
    node->graph = keep ? h : std::move(h);
    return node;
  }
  MetisGraph side[2];
  const auto take_side = [&](int s) { side[s] = induced(h, part, s); };
  if (threads > 1) {
    run_tasks(2, take_side);
  } else {
    take_side(0);
    take_side(1);
  }
  for (idx_t v = 0; v < h.size(); ++v)
    if (part[std::size_t(v)] == 2) node->separator.push_back(h.vertices[std::size_t(v)]);
  if (!keep) h = {};
  const int large = side[1].size() > side[0].size() ? 1 : 0;  // claimed first, with the larger share of threads
  const int share[2] = {threads - threads / 2, std::max(threads / 2, 1)};
  const auto split_side = [&](int task) {
    const int s = task ^ large;
    node->side[s] = split_tree(side[s], rule.below(), share[task]);
  };
  if (threads > 1 && metis_on_threads()) {
    run_tasks(2, split_side);
  } else {
    split_side(0);
    split_side(1);
  }
  return node;
}

//! The parts of `node`'s tree, in elimination order.
void collect_parts(SplitNode& node, std::vector<SplitNode*>& parts) {
  if (node.is_part()) return parts.push_back(&node);
  collect_parts(*node.side[0], parts);
  collect_parts(*node.side[1], parts);
}

//! Orders every part of the tree by METIS_NodeND on `threads` threads, each thread claiming the largest part not
//! yet claimed (the longest orderings start first; none waits for another), and releases the parts' graphs. The
//! orders do not depend on which thread computes them.
void order_parts(SplitNode& root, int threads) {
  std::vector<SplitNode*> parts;
  collect_parts(root, parts);
  std::stable_sort(parts.begin(), parts.end(),
                   [](const SplitNode* a, const SplitNode* b) { return a->graph.size() > b->graph.size(); });
  std::atomic<std::size_t> next{0};
  const auto order_claimed = [&](int) {
    for (std::size_t k = next++; k < parts.size(); k = next++) {
      parts[k]->order = metis_order(parts[k]->graph);
      parts[k]->graph = {};
    }
  };
  const std::size_t workers = metis_on_threads() ? std::size_t(std::max(threads, 1)) : 1;
  run_tasks(int(std::min(workers, parts.size())), order_claimed);
}

//! The tree's order: each split's sides, then its separator; the parts' ranges in it.
void append_order(SplitNode& node, Dissected& d) {
  if (node.is_part()) {
    d.parts.push_back({int(d.order.size()), int(d.order.size() + node.order.size())});
    d.order.insert(d.order.end(), node.order.begin(), node.order.end());
    return;
  }
  append_order(*node.side[0], d);
  append_order(*node.side[1], d);
  d.order.insert(d.order.end(), node.separator.begin(), node.separator.end());
}

//! h's vertices (graph indices) in elimination order: the splits of `rule` (split_tree), then the parts ordered
//! by METIS_NodeND on the threads (order_parts); the result does not depend on `threads`. h is released once split,
//! unless `keep`.
Dissected dissect(MetisGraph& h, SplitRule rule, int threads, bool keep = false) {
  const std::unique_ptr<SplitNode> root = split_tree(h, rule, threads, keep);
  order_parts(*root, threads);
  Dissected d;
  append_order(*root, d);
  return d;
}

//! Levels of dissection for `threads`: one up to two threads, one more for each doubling beyond, so that every
//! thread gets a part to order. Why not more levels everywhere: each level below the first costs some fill
//! (results/records/2026-11-26-tree-parallelism) and pays only where threads order its parts.
int dissection_levels(int threads) {
  int levels = 1;
  while ((1 << levels) < threads && levels < 6) ++levels;
  return levels;
}

//! The splits of an n-vertex graph's dissection on `threads` threads: dissection_levels(threads) levels and, with
//! two or more, every part then larger than the levels' mean part (n / 2^levels) and than kEvenVertices split
//! again. Why: METIS's own balance below the first split leaves parts up to about 1.6 times the mean, and the
//! largest part's ordering ended the dissection on 16 cores while most threads had finished
//! (results/records/2026-11-28-threads); its halves go to two threads (order_parts). The fill stays within 0.2%
//! of the levels' alone on the armadillo TF edits at 4, 8 and 16 threads (the same record).
SplitRule split_rule(idx_t n, int threads) {
  const int levels = dissection_levels(threads);
  return {levels, kSplitUfactor, levels > 1 ? std::max(n >> levels, kEvenVertices) : 0};
}

//! METIS nested dissection whose first dissection_levels(threads) levels are done here, so that their parts can
//! be ordered at once: METIS vertex separators split the graph (the first into nearly equal sides), the parts are
//! ordered by METIS, each separator comes after its sides: METIS_NodeND's own first steps, while the parts'
//! orderings overlap in time. The result depends on the thread count only through the levels: the same for one
//! and two threads. Threads rather than forked processes: a fork write-protects every page of the process, and
//! on a virtual machine whose page faults are slow the faults that follow cost more than a side's ordering
//! (results/records/2026-11-26-ordering-threads). With a guide, the splits are the guide's (bisect). With
//! `postorder`, the order comes postordered as CHOLMOD's analysis postorders it, the parts' elimination trees found
//! on the threads (dissection_postorder.h); the whole graph's lists are then kept for it while the parts are ordered.
std::vector<int> dissected_metis_order(const GraphPattern& pat, int threads, const GraphPattern* guide = nullptr,
                                       bool postorder = false, EliminationTree* tree = nullptr) {
  const idx_t n = pat.n;
  MetisGraph whole = full_graph(pat, guide);
  Dissected d = dissect(whole, split_rule(n, threads), threads, postorder);
  // The parts and the separators together: a permutation of the whole graph.
  std::vector<char> seen(std::size_t(n), 0);
  for (int v : d.order)
    if (v < 0 || v >= n || seen[std::size_t(v)]++)
      throw SolverError("METIS ordering: the dissected ordering is not a permutation");
  if (idx_t(d.order.size()) != n)
    throw SolverError("METIS ordering: the dissected ordering is incomplete");
  if (!postorder) return std::move(d.order);
  return postorder_dissection({pat.n, whole.xadj.data(), whole.adjncy.data()}, d.order, d.parts, threads, tree);
}

}  // namespace

// Below this size METIS takes a few tens of milliseconds and the split would not pay for its bisection.
constexpr int kDissectVertices = 20000;

namespace {

//! CHOLMOD's postordered analysis of g under `given` (perm[new] = old) or, when it is empty, under `method`.
cholmod_factor* analyze_with(const GraphPattern& g, const std::vector<int>& given, const std::string& method,
                             cholmod_common& cc) {
  use_huge_pages_in_suitesparse();
  cc.nmethods = 1;
  cc.method[0].ordering = given.empty() ? cholmod_ordering_code(method) : CHOLMOD_GIVEN;
  cc.postorder = true;
  cholmod_sparse A = cholmod_upper_view(std::size_t(g.n), g.colptr, g.rows, nullptr);
  cholmod_factor* L = given.empty() ? cholmod_analyze(&A, &cc)
                                    : cholmod_analyze_p(&A, const_cast<int*>(given.data()), nullptr, 0, &cc);
  if (!L || cc.status < CHOLMOD_OK) {
    if (L) cholmod_free_factor(&L, &cc);
    throw SolverError(fmt::format("symbolic analysis ({} ordering) of a {}-vertex graph failed, CHOLMOD status {}",
                                  method, g.n, cc.status));
  }
  return L;
}

}  // namespace

bool takes_guide(int n, const std::string& method) {
  // Where the splits form a chain (more than one level): there the guide's cheaper splits shorten the serial path
  // ahead of the parts' orderings. At one level (one or two threads) the one split saves too little to justify
  // moving the bundled meshes' fill (results/records/2026-11-27-guided-splits).
  return method == "metis" && n >= kDissectVertices && dissection_levels(worker_threads()) > 1;
}

namespace {

//! Where an ordering of g under a method comes from: the ordering cache (under its key), a dissection here (on the
//! worker threads, with its guide) or CHOLMOD.
struct OrderingPlan {
  OrderingCache cache;
  bool cacheable, dissected;
  std::string key;
  const GraphPattern* guide;
  int threads;

  std::vector<int> cached(const GraphPattern& g) const { return cacheable ? cache.find(g, key) : std::vector<int>{}; }
  void store(const GraphPattern& g, const int* perm) const {
    if (cacheable) cache.store(g, key, perm);
  }
};

OrderingPlan plan_ordering(const GraphPattern& g, const std::string& method, const GraphPattern* guide) {
  if (guide && guide->n != g.n)
    throw SolverError(fmt::format("ordering: a guide graph of {} vertices for a {}-vertex graph", guide->n, g.n));
  OrderingCache cache = OrderingCache::from_environment();
  const bool cacheable = cache.enabled() && method != "natural";
  const bool dissected = method == "metis" && g.n >= kDissectVertices;
  if (!takes_guide(g.n, method)) guide = nullptr;
  const int threads = worker_threads(), levels = dissection_levels(threads);
  // A dissected ordering depends on its levels and on its guide: the cache keeps one per level count ("metis"
  // for one level) and marks the guided ones, and the ones with evened parts ("-even", split_rule: entries
  // written before it hold other orders).
  const std::string base = guide ? "metis-guided" : "metis";
  std::string key = dissected ? (levels > 1 ? fmt::format("{}{}-even", base, levels) : base) : method;
  return {std::move(cache), cacheable, dissected, std::move(key), guide, threads};
}

}  // namespace

cholmod_factor* analyze_graph(const GraphPattern& g, const std::string& method, cholmod_common& cc,
                              const GraphPattern* guide) {
  const OrderingPlan plan = plan_ordering(g, method, guide);
  std::vector<int> given = plan.cached(g);
  const bool cached = !given.empty();  // postordered already: the analysis keeps it as it is
  if (!cached && plan.dissected) given = dissected_metis_order(g, plan.threads, plan.guide);
  cholmod_factor* L = analyze_with(g, given, method, cc);
  if (!cached) {
    try {
      plan.store(g, static_cast<const int*>(L->Perm));
    } catch (...) {
      cholmod_free_factor(&L, &cc);
      throw;
    }
  }
  return L;
}

std::vector<int> order_graph(const GraphPattern& g, const std::string& method, const GraphPattern* guide,
                             EliminationTree* tree) {
  if (tree) *tree = EliminationTree{};
  const OrderingPlan plan = plan_ordering(g, method, guide);
  std::vector<int> perm = plan.cached(g);
  if (!perm.empty()) return perm;
  if (plan.dissected) {
    // On one thread too: the parts analyzed one after the other take about the time of CHOLMOD's analysis of the
    // whole graph (results/records/2026-11-27-parallel-postorder), and they give the elimination tree that spares
    // a symbolic analysis of the ordered graph its own pass (results/records/2026-11-28-given-tree).
    perm = dissected_metis_order(g, plan.threads, plan.guide, true, tree);
  } else {
    cholmod_common cc;
    cholmod_start(&cc);
    const std::unique_ptr<cholmod_common, int (*)(cholmod_common*)> finish(&cc, cholmod_finish);
    cc.print = 0;
    cc.supernodal = CHOLMOD_SIMPLICIAL;  // only the permutation is wanted
    cholmod_factor* L = analyze_with(g, {}, method, cc);
    const int* p = static_cast<const int*>(L->Perm);
    perm.assign(p, p + g.n);
    cholmod_free_factor(&L, &cc);
  }
  plan.store(g, perm.data());
  return perm;
}

cholmod_factor* analyze_graph_given(const GraphPattern& g, const std::vector<int>& perm, cholmod_common& cc) {
  if (int(perm.size()) != g.n)
    throw SolverError(fmt::format("symbolic analysis: an order of {} entries for a {}-vertex graph", perm.size(), g.n));
  return analyze_with(g, perm, "given", cc);
}

std::vector<int> metis_permutation(const GraphPattern& g) {
  if (g.n >= kDissectVertices) return dissected_metis_order(g, worker_threads());
  MetisGraph whole = full_graph(g);
  return metis_order(whole);
}

}  // namespace db
