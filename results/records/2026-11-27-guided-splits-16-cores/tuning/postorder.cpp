// Scratch timing (not part of the build): what postordering a given vertex order costs. On a 2-ring pattern written
// by ../../2026-11-26-analysis-levers/tuning/dump_pattern.cpp, with CHOLMOD's METIS order as the given order, five
// repetitions of: CHOLMOD's simplicial analysis under that order, postordered (what the vertex ordering does), and
// the cheaper path (the permuted pattern transposed twice, its elimination tree, an unweighted postorder); and how
// many positions of the two postordered orders agree (CHOLMOD weights its postorder by the column counts).
//   g++ -O2 -o postorder postorder.cpp -I/usr/include/suitesparse -lcholmod -lmetis
//   ./postorder g104.bin
#include <metis.h>
#include <cholmod.h>
#include <cstdio>
#include <ctime>
#include <vector>
using namespace std;
static double now() { timespec t; clock_gettime(CLOCK_MONOTONIC, &t); return t.tv_sec + 1e-9 * t.tv_nsec; }
int main(int argc, char** argv) {
  FILE* F = fopen(argv[1], "rb"); int n; long long nz; fread(&n, 4, 1, F); fread(&nz, 8, 1, F);
  vector<int> p(n + 1), i(nz); fread(p.data(), 4, n + 1, F); fread(i.data(), 4, nz, F); fclose(F);
  cholmod_common cc; cholmod_start(&cc); cc.print = 0;
  cholmod_sparse A{}; A.nrow = A.ncol = n; A.nzmax = nz; A.p = p.data(); A.i = i.data();
  A.stype = 1; A.itype = CHOLMOD_INT; A.xtype = CHOLMOD_PATTERN; A.dtype = CHOLMOD_DOUBLE; A.sorted = 1; A.packed = 1;
  // a fill-reducing perm: CHOLMOD's METIS
  cc.nmethods = 1; cc.method[0].ordering = CHOLMOD_METIS; cc.postorder = 0; cc.supernodal = CHOLMOD_SIMPLICIAL;
  cholmod_factor* L0 = cholmod_analyze(&A, &cc);
  vector<int> perm((int*)L0->Perm, (int*)L0->Perm + n); cholmod_free_factor(&L0, &cc);
  for (int rep = 0; rep < 5; ++rep) {
    double t0 = now();
    cc.method[0].ordering = CHOLMOD_GIVEN; cc.postorder = 1;
    cholmod_factor* L = cholmod_analyze_p(&A, perm.data(), nullptr, 0, &cc);
    double t1 = now();
    // cheap: C = A(p,p) transposed to lower? etree of upper sym: cholmod_etree takes A with stype>0 -> uses A
    cholmod_sparse* C = cholmod_ptranspose(&A, 0, perm.data(), nullptr, 0, &cc);  // C = A(p,p)' : lower -> stype -1
    cholmod_sparse* Ct = cholmod_transpose(C, 0, &cc);  // upper
    vector<int> parent(n), post(n);
    cholmod_etree(Ct, parent.data(), &cc);
    cholmod_postorder(parent.data(), n, nullptr, post.data(), &cc);
    double t2 = now();
    int same = 0; for (int k = 0; k < n; ++k) same += ((int*)L->Perm)[k] == perm[post[k]];
    printf("analyze_p %.4f  etree+postorder %.4f  same %d of %d  stype C %d\n", t1 - t0, t2 - t1, same, n, C->stype);
    cholmod_free_sparse(&C, &cc); cholmod_free_sparse(&Ct, &cc); cholmod_free_factor(&L, &cc);
  }
}
