#include "systems/vertex_ordering.h"

#include <cholmod.h>

#include <exception>
#include <memory>
#include <thread>

#include "solvers/base/error.h"
#include "core/timer.h"
#include "solvers/ordering/graph_ordering.h"
#include "solvers/ordering/ring_dissection.h"
#include "systems/build_detail.h"

namespace db {

namespace {

//! Renumbers unk's unknowns by perm (perm[new] = old).
void renumber(const int* perm, Unknowns& unk) {
  unk.tree.reset();  // of the former numbering
  const std::vector<int> old = unk.unknown_vertices;
  for (int p = 0; p < unk.num_unknowns(); ++p) {
    unk.unknown_vertices[p] = old[perm[p]];
    unk.unknown_of[unk.unknown_vertices[p]] = p;
  }
}

//! CHOLMOD's common set for an analysis that only wants the permutation.
struct PermutationCommon {
  cholmod_common cc;
  PermutationCommon() {
    cholmod_start(&cc);
    cc.print = 0;
    cc.supernodal = CHOLMOD_SIMPLICIAL;  // only the permutation is wanted; skip the supernodal symbolic phase
  }
  ~PermutationCommon() { cholmod_finish(&cc); }
};

void check_method(const std::string& method) {
  if (method != "amd" && method != "metis" && method != "nesdis" && method != "ringnd")
    throw InputError("unknown vertex ordering '" + method + "' (expected amd, metis, nesdis or ringnd)");
}

}  // namespace

void order_unknowns(const Adjacency& adj, Unknowns& unk, const std::string& method) {
  check_method(method);
  if (method != "ringnd") {
    // Upper triangle of the unknowns' 2-ring interaction graph, pattern only.
    order_unknowns(interaction_pattern(adj, unk), unk, method, &adj);
    return;
  }
  // Dissected on the 1-ring graph; the postordering analysis then runs on the 2-ring graph.
  const std::vector<int> perm = ring_dissection_order(
      {adj.num_vertices(), adj.off.data(), adj.nbr.data(), unk.unknown_of.data(), unk.num_unknowns()});
  const InteractionPattern pat = interaction_pattern(adj, unk);
  PermutationCommon c;
  cholmod_factor* L = analyze_graph_given({unk.num_unknowns(), pat.colptr.data(), pat.rows.data()}, perm, c.cc);
  renumber(static_cast<const int*>(L->Perm), unk);
  cholmod_free_factor(&L, &c.cc);
}

void order_unknowns(const InteractionPattern& pat, Unknowns& unk, const std::string& method, const Adjacency* adj) {
  check_method(method);
  if (method == "ringnd")
    throw InputError("vertex ordering 'ringnd' needs the vertex adjacency, not the 2-ring pattern");
  const int n = unk.num_unknowns();
  // METIS's splits on the 1-ring graph where the ordering takes a guide.
  const bool guided = adj && takes_guide(n, method);
  const InteractionPattern one_ring = guided ? interaction_pattern(*adj, unk, 1) : InteractionPattern{};
  const GraphPattern guide{n, one_ring.colptr.data(), one_ring.rows.data()};
  auto tree = std::make_shared<EliminationTree>();
  renumber(order_graph({n, pat.colptr.data(), pat.rows.data()}, method, guided ? &guide : nullptr, tree.get()).data(),
           unk);
  if (!tree->parent.empty()) unk.tree = std::move(tree);
}

NormalSystem build_structured_while_ordering(const EnergyOperator& op, Unknowns& unk, const std::string& method,
                                             std::size_t byte_budget, double& ordering_seconds) {
  check_build(op, unk, Build::Structured, byte_budget);
  Timer wall;
  const InteractionPattern pat = interaction_pattern(op.adjacency(), unk);
  Unknowns ordered = unk;
  std::exception_ptr error;
  std::thread orderer([&] {
    try {
      Timer t;
      order_unknowns(pat, ordered, method);
      ordering_seconds = t.seconds();
    } catch (...) {
      error = std::current_exception();
    }
  });
  NormalSystem sys;
  try {
    sys = detail::build_structured(op, unk, &pat, 1);  // the other core orders
  } catch (...) {
    orderer.join();
    throw;
  }
  orderer.join();
  if (error) std::rethrow_exception(error);
  sys.build = Build::Structured;
  sys.block = op.block();
  sys.rhs_cols = op.rhs_cols();
  sys.held_bytes.emplace_back("K_upper_renumbering", sparse_bytes(sys.K));
  std::vector<int> new_of_old(static_cast<std::size_t>(unk.num_unknowns()));
  for (std::size_t u = 0; u < new_of_old.size(); ++u)
    new_of_old[u] = ordered.unknown_of[static_cast<std::size_t>(unk.unknown_vertices[u])];
  renumber_unknowns(sys, new_of_old);
  unk = std::move(ordered);
  sys.build_seconds = wall.seconds();
  return sys;
}

}  // namespace db
