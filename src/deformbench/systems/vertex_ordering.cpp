#include "systems/vertex_ordering.h"

#include <cholmod.h>

#include <memory>

#include <fmt/format.h>

#include "core/error.h"
#include "solvers/cholmod_views.h"

namespace db {

void order_unknowns(const Adjacency& adj, Unknowns& unk, const std::string& method) {
  if (method != "amd" && method != "metis" && method != "nesdis")
    throw InputError("unknown vertex ordering '" + method + "' (expected amd, metis or nesdis)");
  const int ordering = cholmod_ordering_code(method);

  const int nu = unk.num_unknowns();
  // Upper triangle of the unknowns' 2-ring interaction graph, pattern only.
  InteractionPattern pat = interaction_pattern(adj, unk);
  std::vector<int>& colptr = pat.colptr;
  std::vector<int>& rows = pat.rows;

  cholmod_common cc;
  cholmod_start(&cc);
  std::unique_ptr<cholmod_common, int (*)(cholmod_common*)> guard(&cc, cholmod_finish);
  cc.nmethods = 1;
  cc.method[0].ordering = ordering;
  cc.postorder = true;
  cc.supernodal = CHOLMOD_SIMPLICIAL;  // only the permutation is wanted; skip the supernodal symbolic phase
  cholmod_sparse A = cholmod_upper_view(std::size_t(nu), colptr.data(), rows.data(), nullptr);
  cholmod_factor* L = cholmod_analyze(&A, &cc);
  if (!L || cc.status < CHOLMOD_OK)
    throw SolverError(fmt::format("vertex ordering ({}) failed with CHOLMOD status {}", method, cc.status));
  const int* perm = static_cast<const int*>(L->Perm);
  std::vector<int> old = unk.unknown_vertices;
  for (int p = 0; p < nu; ++p) {
    unk.unknown_vertices[p] = old[perm[p]];
    unk.unknown_of[unk.unknown_vertices[p]] = p;
  }
  cholmod_free_factor(&L, &cc);
}

}  // namespace db
