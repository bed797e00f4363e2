// Scratch timing (not part of the build): the two serial CHOLMOD analyses that follow the vertex ordering, and two
// ways to cut them. On a 2-ring pattern written by ../../2026-11-26-analysis-levers/tuning/dump_pattern.cpp, with
// CHOLMOD's METIS order as the given order, five repetitions of:
//   (a) the simplicial analysis under the given order, postordered (what order_unknowns does);
//   (e) the cheaper postordering: the permuted pattern transposed twice, its elimination tree, an unweighted
//       postorder (and how many positions agree with (a)'s order: CHOLMOD weights its postorder by column counts);
//   (b) the supernodal analysis of the pattern renumbered by (a)'s order, natural ordering, the multifrontal
//       backend's relaxation for 3x3 blocks (what analyze_blocks does);
//   (c) one supernodal analysis under the given order, postordered, the same relaxation: whether it gives (a)'s
//       order and (b)'s supernodes, and in how much time.
//   g++ -O2 -o analyses analyses.cpp -I/usr/include/suitesparse -lcholmod
//   ./analyses g104.bin
#include <cholmod.h>
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <vector>
using namespace std;
static double now() { timespec t; clock_gettime(CLOCK_MONOTONIC, &t); return t.tv_sec + 1e-9 * t.tv_nsec; }
void relax(cholmod_common& cc) { for (int k = 0; k < 3; ++k) cc.nrelax[k] = max<size_t>(1, (cc.nrelax[k] + 2) / 3); }
struct Common {  // a cholmod_common for one analysis: ordering, postorder, simplicial or supernodal
  cholmod_common cc;
  Common(int ordering, bool supernodal) {
    cholmod_start(&cc); cc.print = 0; cc.nmethods = 1; cc.method[0].ordering = ordering; cc.postorder = 1;
    cc.supernodal = supernodal ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
    if (supernodal) relax(cc);
  }
  ~Common() { cholmod_finish(&cc); }
};
int main(int argc, char** argv) {
  FILE* F = fopen(argv[1], "rb"); int n; long long nz;
  if (!F || fread(&n, 4, 1, F) != 1 || fread(&nz, 8, 1, F) != 1) return 1;
  vector<int> p(n + 1), i(nz);
  if (fread(p.data(), 4, n + 1, F) != size_t(n + 1) || fread(i.data(), 4, nz, F) != size_t(nz)) return 1;
  fclose(F);
  cholmod_sparse A{}; A.nrow = A.ncol = n; A.nzmax = nz; A.p = p.data(); A.i = i.data();
  A.stype = 1; A.itype = CHOLMOD_INT; A.xtype = CHOLMOD_PATTERN; A.dtype = CHOLMOD_DOUBLE; A.sorted = 1; A.packed = 1;
  vector<int> perm(n);
  { Common m(CHOLMOD_METIS, false); m.cc.postorder = 0;  // the given order: CHOLMOD's METIS
    cholmod_factor* L0 = cholmod_analyze(&A, &m.cc); copy((int*)L0->Perm, (int*)L0->Perm + n, perm.begin());
    cholmod_free_factor(&L0, &m.cc); }
  for (int rep = 0; rep < 5; ++rep) {
    Common a(CHOLMOD_GIVEN, false), b(CHOLMOD_NATURAL, true), c(CHOLMOD_GIVEN, true);
    double t0 = now(); cholmod_factor* La = cholmod_analyze_p(&A, perm.data(), nullptr, 0, &a.cc); double ta = now() - t0;
    const vector<int> P((int*)La->Perm, (int*)La->Perm + n);
    t0 = now();
    cholmod_sparse* C = cholmod_ptranspose(&A, 0, perm.data(), nullptr, 0, &a.cc);  // the lower triangle of A(p,p)
    cholmod_sparse* Cu = cholmod_transpose(C, 0, &a.cc);                            // its upper triangle
    vector<int> parent(n), post(n);
    cholmod_etree(Cu, parent.data(), &a.cc); cholmod_postorder(parent.data(), n, nullptr, post.data(), &a.cc);
    double te = now() - t0;
    int agree = 0; for (int k = 0; k < n; ++k) agree += P[k] == perm[post[k]];
    cholmod_free_sparse(&C, &a.cc); cholmod_free_sparse(&Cu, &a.cc);
    C = cholmod_ptranspose(&A, 0, const_cast<int*>(P.data()), nullptr, 0, &a.cc); Cu = cholmod_transpose(C, 0, &a.cc);
    cholmod_sort(Cu, &a.cc);  // the renumbered pattern, upper: what the backend analyzes
    t0 = now(); cholmod_factor* Lb = cholmod_analyze(Cu, &b.cc); double tb = now() - t0;
    t0 = now(); cholmod_factor* Lc = cholmod_analyze_p(&A, perm.data(), nullptr, 0, &c.cc); double tc = now() - t0;
    bool identity = true; for (int k = 0; k < n; ++k) identity = identity && ((int*)Lb->Perm)[k] == k;
    const bool same_order = equal(P.begin(), P.end(), (int*)Lc->Perm);
    const bool same_supernodes = Lb->nsuper == Lc->nsuper &&
      equal((int*)Lb->super, (int*)Lb->super + Lb->nsuper + 1, (int*)Lc->super) &&
      equal((int*)Lb->pi, (int*)Lb->pi + Lb->nsuper + 1, (int*)Lc->pi);
    printf("%s a %.4f e %.4f b %.4f c %.4f agree %d of %d b_identity %d c_order_is_a %d c_supernodes_are_b %d\n",
           argv[1], ta, te, tb, tc, agree, n, identity, same_order, same_supernodes);
    cholmod_free_factor(&La, &a.cc); cholmod_free_factor(&Lb, &b.cc); cholmod_free_factor(&Lc, &c.cc);
    cholmod_free_sparse(&C, &a.cc); cholmod_free_sparse(&Cu, &a.cc);
  }
}
