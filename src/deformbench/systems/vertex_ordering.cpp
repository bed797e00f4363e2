#include "systems/vertex_ordering.h"

#include <cholmod.h>

#include <algorithm>
#include <memory>

#include <fmt/format.h>

#include "core/error.h"

namespace db {

void order_unknowns(const Adjacency& adj, Unknowns& unk, const std::string& method) {
  int ordering = 0;
  if (method == "amd") ordering = CHOLMOD_AMD;
  else if (method == "metis") ordering = CHOLMOD_METIS;
  else if (method == "nesdis") ordering = CHOLMOD_NESDIS;
  else throw InputError("unknown vertex ordering '" + method + "' (expected amd, metis or nesdis)");

  const int nu = unk.num_unknowns();
  // Upper triangle (row <= column) of the unknowns' 2-ring interaction graph, pattern only.
  std::vector<int> colptr(nu + 1, 0), rows;
  rows.reserve(static_cast<std::size_t>(nu) * 10);
  std::vector<int> mark(nu, -1), col;
  for (int ku = 0; ku < nu; ++ku) {
    const int k = unk.unknown_vertices[ku];
    col.clear();
    auto visit = [&](int j) {
      const int ju = unk.unknown_of[j];
      if (ju < 0 || ju > ku || mark[ju] == ku) return;
      mark[ju] = ku;
      col.push_back(ju);
    };
    visit(k);
    for (const int* a = adj.begin(k); a != adj.end(k); ++a) {
      visit(*a);
      for (const int* c = adj.begin(*a); c != adj.end(*a); ++c) visit(*c);
    }
    std::sort(col.begin(), col.end());
    rows.insert(rows.end(), col.begin(), col.end());
    colptr[ku + 1] = static_cast<int>(rows.size());
  }

  cholmod_common cc;
  cholmod_start(&cc);
  std::unique_ptr<cholmod_common, int (*)(cholmod_common*)> guard(&cc, cholmod_finish);
  cc.nmethods = 1;
  cc.method[0].ordering = ordering;
  cc.postorder = true;
  cc.supernodal = CHOLMOD_SIMPLICIAL;  // only the permutation is wanted; skip the supernodal symbolic phase
  cholmod_sparse A{};
  A.nrow = A.ncol = nu;
  A.nzmax = rows.size();
  A.p = colptr.data();
  A.i = rows.data();
  A.stype = 1;
  A.itype = CHOLMOD_INT;
  A.xtype = CHOLMOD_PATTERN;
  A.dtype = CHOLMOD_DOUBLE;
  A.sorted = true;
  A.packed = true;
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
