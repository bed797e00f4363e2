// Scratch: where CHOLMOD's supernodal analysis of a postordered vertex pattern (what the multifrontal backend runs on
// the ordered block graph) spends its time: the whole cholmod_analyze (natural order, supernodal) against the tree
// and counts (cholmod_analyze_ordering) plus cholmod_super_symbolic given them. Five rounds per pattern.
//   g++ -O2 -o backend_analysis backend_analysis.cpp -I../../2026-11-27-guided-splits-16-cores/tuning
//     -I/usr/include/suitesparse -lcholmod -lmetis   (one command)
//   ./backend_analysis PATTERN   (PATTERN: a dumped 2-ring pattern, as postorder_bench.sh's)
#include <numeric>

#include "dissect_common.h"  // now(), G and load() of the dumped patterns
cholmod_sparse view(G& g) {
  cholmod_sparse A{}; A.nrow = A.ncol = g.n; A.nzmax = g.i.size(); A.p = g.p.data(); A.i = g.i.data();
  A.stype = 1; A.itype = CHOLMOD_INT; A.xtype = CHOLMOD_PATTERN; A.dtype = CHOLMOD_DOUBLE; A.sorted = 1; A.packed = 1;
  return A;
}
int main(int argc, char** argv) {
  G g0 = load(argv[1]);
  cholmod_common cc; cholmod_start(&cc); cc.print = 0;
  // Postorder a METIS order, then permute the pattern into it (as the structured build does).
  cc.nmethods = 1; cc.method[0].ordering = CHOLMOD_METIS; cc.postorder = 1; cc.supernodal = CHOLMOD_SIMPLICIAL;
  cholmod_sparse A0 = view(g0);
  cholmod_factor* L0 = cholmod_analyze(&A0, &cc);
  cholmod_sparse* P = cholmod_ptranspose(&A0, 0, (int*)L0->Perm, nullptr, 0, &cc);  // lower of A(p,p)
  cholmod_sparse* Pu = cholmod_transpose(P, 0, &cc);  // upper
  cholmod_free_factor(&L0, &cc);
  cholmod_sort(Pu, &cc);
  for (int round = 0; round < 5; ++round) {
    cc.nmethods = 1; cc.method[0].ordering = CHOLMOD_NATURAL; cc.postorder = 1; cc.supernodal = CHOLMOD_SUPERNODAL;
    double t0 = now();
    cholmod_factor* L = cholmod_analyze(Pu, &cc);
    double t1 = now();
    const int n = g0.n;
    vector<int> perm(n), parent(n), post(n), count(n), first(n), level(n);
    iota(perm.begin(), perm.end(), 0);
    double t2 = now();
    cholmod_analyze_ordering(Pu, CHOLMOD_NATURAL, perm.data(), nullptr, 0, parent.data(), post.data(), count.data(), first.data(), level.data(), &cc);
    double t3 = now();
    cholmod_factor* L2 = cholmod_allocate_factor(n, &cc);
    for (int k = 0; k < n; ++k) ((int*)L2->ColCount)[k] = count[k];
    // super_symbolic wants the pattern's transpose as F for unsymmetric; for symmetric upper, F = NULL and A upper
    double t4 = now();
    int ok = cholmod_super_symbolic(Pu, nullptr, parent.data(), L2, &cc);
    double t5 = now();
    printf("round %d whole %.4f tree+counts %.4f super_symbolic %.4f ok %d nsuper %zu/%zu\n", round,
           t1 - t0, t3 - t2, t5 - t4, ok, L->nsuper, L2->nsuper);
    cholmod_free_factor(&L, &cc); cholmod_free_factor(&L2, &cc);
  }
  cholmod_finish(&cc);
}
