#include "systems/vertex_ordering.h"

#include <cholmod.h>

#include <memory>

#include "core/error.h"
#include "solvers/graph_ordering.h"

namespace db {

void order_unknowns(const Adjacency& adj, Unknowns& unk, const std::string& method) {
  if (method != "amd" && method != "metis" && method != "nesdis")
    throw InputError("unknown vertex ordering '" + method + "' (expected amd, metis or nesdis)");
  const int nu = unk.num_unknowns();
  // Upper triangle of the unknowns' 2-ring interaction graph, pattern only.
  const InteractionPattern pat = interaction_pattern(adj, unk);

  cholmod_common cc;
  cholmod_start(&cc);
  const std::unique_ptr<cholmod_common, int (*)(cholmod_common*)> guard(&cc, cholmod_finish);
  cc.print = 0;
  cc.supernodal = CHOLMOD_SIMPLICIAL;  // only the permutation is wanted; skip the supernodal symbolic phase
  cholmod_factor* L = analyze_graph({nu, pat.colptr.data(), pat.rows.data()}, method, cc);
  const int* perm = static_cast<const int*>(L->Perm);
  const std::vector<int> old = unk.unknown_vertices;
  for (int p = 0; p < nu; ++p) {
    unk.unknown_vertices[p] = old[perm[p]];
    unk.unknown_of[unk.unknown_vertices[p]] = p;
  }
  cholmod_free_factor(&L, &cc);
}

}  // namespace db
