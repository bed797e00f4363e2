#include "solvers/ordering/graph_ordering.h"

#include <memory>
#include <optional>
#include <vector>

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "solvers/base/resources.h"
#include "solvers/ordering/child_task.h"
#include "solvers/ordering/cholmod_views.h"
#include "solvers/ordering/ordering_cache.h"

namespace db {
namespace {

using CommonPtr = std::unique_ptr<cholmod_common, int (*)(cholmod_common*)>;

//! A subgraph: its upper pattern (vertices renumbered 0..n-1 in ascending order) and the graph index of each
//! vertex.
struct SubGraph {
  std::vector<int> colptr, rows, vertices;
  std::size_t size() const { return vertices.size(); }
};

//! The subgraph of g induced by its vertices v with part[v] == which.
SubGraph induced(const GraphPattern& g, const std::vector<int>& part, int which) {
  SubGraph h;
  std::vector<int> local(static_cast<std::size_t>(g.n), -1);
  for (int v = 0; v < g.n; ++v)
    if (part[v] == which) {
      local[v] = static_cast<int>(h.vertices.size());
      h.vertices.push_back(v);
    }
  h.colptr.reserve(h.size() + 1);
  h.colptr.push_back(0);
  for (int v : h.vertices) {
    for (int q = g.colptr[v]; q < g.colptr[v + 1]; ++q)
      if (const int r = local[static_cast<std::size_t>(g.rows[q])]; r >= 0) h.rows.push_back(r);
    h.colptr.push_back(static_cast<int>(h.rows.size()));
  }
  return h;
}

//! METIS nested dissection of g, as indices in elimination order: vertices[k] for vertex k when given, else k.
//! Unpostordered: the analysis of the whole graph postorders at the end.
std::vector<int> metis_order(const GraphPattern& g, const std::vector<int>* vertices = nullptr) {
  const std::size_t n = std::size_t(g.n);
  if (n == 0) return {};
  cholmod_common cc;
  cholmod_start(&cc);
  const CommonPtr guard(&cc, cholmod_finish);
  cc.print = 0;
  cholmod_sparse A = cholmod_upper_view(n, g.colptr, g.rows, nullptr);
  std::vector<int> perm(n);
  if (!cholmod_metis(&A, nullptr, 0, false, perm.data(), &cc))
    throw SolverError(fmt::format("METIS ordering failed on {} vertices, CHOLMOD status {}", n, cc.status));
  if (vertices)
    for (int& p : perm) p = (*vertices)[static_cast<std::size_t>(p)];
  return perm;
}
std::vector<int> metis_order(const SubGraph& g) {
  return metis_order({int(g.size()), g.colptr.data(), g.rows.data()}, &g.vertices);
}

//! METIS nested dissection whose first level is done here, so that the two sides can be ordered at once: a
//! METIS vertex separator splits the graph, each side is ordered by METIS (the smaller one in a child process
//! when there are two worker threads), the separator comes last. METIS_NodeND takes the same first step itself,
//! so the fill stays that of METIS run whole, while the two sides' orderings overlap in time. The result does
//! not depend on the thread count. A second level (four parts, better balanced) was tried and dropped: on the
//! bundled meshes it cost more flops and a larger factor than its balance saved. Empty if the bisection fails
//! (the caller then runs METIS whole).
std::vector<int> dissected_metis_order(const GraphPattern& pat, cholmod_common& cc) {
  const int n = pat.n;
  std::vector<int> part(static_cast<std::size_t>(n));
  cholmod_sparse A = cholmod_upper_view(std::size_t(n), pat.colptr, pat.rows, nullptr);
  if (cholmod_bisect(&A, nullptr, 0, true, part.data(), &cc) < 0) return {};
  const SubGraph side[2] = {induced(pat, part, 0), induced(pat, part, 1)};
  const int small = side[1].size() < side[0].size() ? 1 : 0;

  std::vector<int> order[2];
  {
    std::optional<ChildTask> child;
    if (worker_threads() > 1) child.emplace(side[small].size(), [&] { return metis_order(side[small]); });
    order[1 - small] = metis_order(side[1 - small]);
    if (child)
      if (auto got = child->result()) order[small] = std::move(*got);
  }
  if (order[small].size() != side[small].size()) order[small] = metis_order(side[small]);

  std::vector<int> perm;
  perm.reserve(static_cast<std::size_t>(n));
  for (const auto& o : order) perm.insert(perm.end(), o.begin(), o.end());
  for (int v = 0; v < n; ++v)
    if (part[v] == 2) perm.push_back(v);
  // A child's answer is checked like any input: together, a permutation of the whole graph.
  std::vector<char> seen(static_cast<std::size_t>(n), 0);
  for (int v : perm)
    if (v < 0 || v >= n || seen[v]++)
      throw SolverError("METIS ordering: the dissected ordering is not a permutation");
  if (static_cast<int>(perm.size()) != n)
    throw SolverError("METIS ordering: the dissected ordering is incomplete");
  return perm;
}

}  // namespace

// Below this size METIS takes a few tens of milliseconds and the split would not pay for its bisection.
constexpr int kDissectVertices = 20000;

namespace {

//! CHOLMOD's postordered analysis of g under `given` (perm[new] = old) or, when it is empty, under `method`.
cholmod_factor* analyze_with(const GraphPattern& g, const std::vector<int>& given, const std::string& method,
                             cholmod_common& cc) {
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

cholmod_factor* analyze_graph(const GraphPattern& g, const std::string& method, cholmod_common& cc) {
  const OrderingCache cache = OrderingCache::from_environment();
  const bool cacheable = cache.enabled() && method != "natural";
  std::vector<int> given = cacheable ? cache.find(g, method) : std::vector<int>{};
  const bool cached = !given.empty();  // postordered already: the analysis keeps it as it is
  if (!cached && method == "metis" && g.n >= kDissectVertices) given = dissected_metis_order(g, cc);
  cholmod_factor* L = analyze_with(g, given, method, cc);
  if (cacheable && !cached) {
    try {
      cache.store(g, method, static_cast<const int*>(L->Perm));
    } catch (...) {
      cholmod_free_factor(&L, &cc);
      throw;
    }
  }
  return L;
}

cholmod_factor* analyze_graph_given(const GraphPattern& g, const std::vector<int>& perm, cholmod_common& cc) {
  if (int(perm.size()) != g.n)
    throw SolverError(fmt::format("symbolic analysis: an order of {} entries for a {}-vertex graph", perm.size(), g.n));
  return analyze_with(g, perm, "given", cc);
}

std::vector<int> metis_permutation(const GraphPattern& g) {
  if (g.n >= kDissectVertices) {
    cholmod_common cc;
    cholmod_start(&cc);
    const CommonPtr guard(&cc, cholmod_finish);
    cc.print = 0;
    if (std::vector<int> perm = dissected_metis_order(g, cc); !perm.empty()) return perm;
  }
  return metis_order(g);
}

}  // namespace db
