// Scratch timing (not part of the build): could the vertex ordering's postordering analysis and the multifrontal
// backend's supernodal analysis be one CHOLMOD analysis? On a 2-ring pattern written by
// ../../2026-11-26-analysis-levers/tuning/dump_pattern.cpp, with CHOLMOD's METIS order as the given order, five
// repetitions of: (a) the simplicial analysis under the given order, postordered (what order_unknowns does);
// (b) the supernodal analysis of the pattern renumbered by (a)'s order, natural ordering, the backend's relaxation
// for 3x3 blocks (what analyze_blocks does); (c) one supernodal analysis under the given order, postordered, the
// same relaxation. Prints the three times, whether (b) keeps the identity order, and whether (c) gives (a)'s order
// and (b)'s supernodes.
//   g++ -O2 -o shared_analysis shared_analysis.cpp -I/usr/include/suitesparse -lcholmod
//   ./shared_analysis g104.bin
#include <cholmod.h>
#include <cstdio>
#include <ctime>
#include <vector>
#include <algorithm>
using namespace std;
static double now() { timespec t; clock_gettime(CLOCK_MONOTONIC, &t); return t.tv_sec + 1e-9 * t.tv_nsec; }
void relax(cholmod_common& cc) { for (int k = 0; k < 3; ++k) cc.nrelax[k] = max<size_t>(1, (cc.nrelax[k] + 2) / 3); }
int main(int argc, char** argv) {
  FILE* F = fopen(argv[1], "rb"); int n; long long nz; fread(&n, 4, 1, F); fread(&nz, 8, 1, F);
  vector<int> p(n + 1), i(nz); fread(p.data(), 4, n + 1, F); fread(i.data(), 4, nz, F); fclose(F);
  cholmod_common cc; cholmod_start(&cc); cc.print = 0;
  cholmod_sparse A{}; A.nrow = A.ncol = n; A.nzmax = nz; A.p = p.data(); A.i = i.data();
  A.stype = 1; A.itype = CHOLMOD_INT; A.xtype = CHOLMOD_PATTERN; A.dtype = CHOLMOD_DOUBLE; A.sorted = 1; A.packed = 1;
  cc.nmethods = 1; cc.method[0].ordering = CHOLMOD_METIS; cc.postorder = 0; cc.supernodal = CHOLMOD_SIMPLICIAL;
  cholmod_factor* L0 = cholmod_analyze(&A, &cc);
  vector<int> perm((int*)L0->Perm, (int*)L0->Perm + n); cholmod_free_factor(&L0, &cc);
  for (int rep = 0; rep < 5; ++rep) {
    // (a) the vertex ordering's postordering analysis: simplicial, given perm
    cholmod_common ca; cholmod_start(&ca); ca.print = 0; ca.nmethods = 1; ca.method[0].ordering = CHOLMOD_GIVEN; ca.postorder = 1; ca.supernodal = CHOLMOD_SIMPLICIAL;
    double t0 = now(); cholmod_factor* La = cholmod_analyze_p(&A, perm.data(), nullptr, 0, &ca); double ta = now() - t0;
    vector<int> P((int*)La->Perm, (int*)La->Perm + n);
    // the renumbered pattern, upper (what the multifrontal backend's block pattern is)
    cholmod_sparse* C = cholmod_ptranspose(&A, 0, P.data(), nullptr, 0, &ca); cholmod_sparse* Cu = cholmod_transpose(C, 0, &ca); cholmod_sort(Cu, &ca);
    // (b) the backend's supernodal analysis, natural
    cholmod_common cb; cholmod_start(&cb); cb.print = 0; cb.nmethods = 1; cb.method[0].ordering = CHOLMOD_NATURAL; cb.postorder = 1; cb.supernodal = CHOLMOD_SUPERNODAL; relax(cb);
    t0 = now(); cholmod_factor* Lb = cholmod_analyze(Cu, &cb); double tb = now() - t0;
    // (c) merged: supernodal, given perm
    cholmod_common cm; cholmod_start(&cm); cm.print = 0; cm.nmethods = 1; cm.method[0].ordering = CHOLMOD_GIVEN; cm.postorder = 1; cm.supernodal = CHOLMOD_SUPERNODAL; relax(cm);
    t0 = now(); cholmod_factor* Lc = cholmod_analyze_p(&A, perm.data(), nullptr, 0, &cm); double tc = now() - t0;
    bool identity = true; for (int k = 0; k < n; ++k) identity = identity && ((int*)Lb->Perm)[k] == k;
    bool sameperm = equal(P.begin(), P.end(), (int*)Lc->Perm);
    bool samesuper = Lb->nsuper == Lc->nsuper && equal((int*)Lb->super, (int*)Lb->super + Lb->nsuper + 1, (int*)Lc->super)
      && equal((int*)Lb->pi, (int*)Lb->pi + Lb->nsuper + 1, (int*)Lc->pi);
    printf("simplicial given %.4f  supernodal natural %.4f  supernodal given %.4f  | b identity %d  c perm = a perm %d  same supernodes %d\n",
           ta, tb, tc, identity, sameperm, samesuper);
    cholmod_free_factor(&La, &ca); cholmod_free_factor(&Lb, &cb); cholmod_free_factor(&Lc, &cm);
    cholmod_free_sparse(&C, &ca); cholmod_free_sparse(&Cu, &ca); cholmod_finish(&ca); cholmod_finish(&cb); cholmod_finish(&cm);
  }
}
