// Scratch: SCOTCH's nested dissection (strategy strings) against METIS_NodeND on a dumped 2-ring pattern:
// wall time, nnz(L) and flops (CHOLMOD's symbolic count under the order).
// Built and run by study.sh:
//   ./scotch_fill PATTERN metis|scotch SEED [STRATEGY] [threads]   (SEED: METIS_OPTION_SEED, or SCOTCH's context seed)
#include <cholmod.h>
#include <metis.h>
#include <scotch.h>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>
using namespace std;
static double now() { timespec t; clock_gettime(CLOCK_MONOTONIC, &t); return t.tv_sec + 1e-9 * t.tv_nsec; }
struct G { int n; vector<int> p, i; };
G load(const char* f) {
  FILE* F = fopen(f, "rb"); G g; long long nz; if (fread(&g.n, 4, 1, F) != 1 || fread(&nz, 8, 1, F) != 1) exit(3);
  g.p.resize(g.n + 1); g.i.resize(nz);
  if (fread(g.p.data(), 4, g.n + 1, F) != size_t(g.n + 1) || fread(g.i.data(), 4, nz, F) != size_t(nz)) exit(3);
  fclose(F); return g;
}
template <class I> void full(const G& g, vector<I>& xadj, vector<I>& adj) {
  vector<I> deg(g.n, 0);
  for (int j = 0; j < g.n; ++j) for (int q = g.p[j]; q < g.p[j + 1]; ++q) { int r = g.i[q]; if (r != j) { deg[r]++; deg[j]++; } }
  xadj.assign(g.n + 1, 0); for (int j = 0; j < g.n; ++j) xadj[j + 1] = xadj[j] + deg[j];
  adj.resize(xadj[g.n]); vector<I> pos(xadj.begin(), xadj.end() - 1);
  for (int j = 0; j < g.n; ++j) for (int q = g.p[j]; q < g.p[j + 1]; ++q) { int r = g.i[q]; if (r != j) { adj[pos[r]++] = j; adj[pos[j]++] = r; } }
}
void stats(G& g, const vector<int>& perm, double& lnz, double& fl) {
  cholmod_common cc; cholmod_start(&cc); cc.print = 0;
  cc.nmethods = 1; cc.method[0].ordering = CHOLMOD_GIVEN; cc.postorder = 1; cc.supernodal = CHOLMOD_SIMPLICIAL;
  cholmod_sparse A{}; A.nrow = A.ncol = g.n; A.nzmax = g.i.size(); A.p = g.p.data(); A.i = g.i.data();
  A.stype = 1; A.itype = CHOLMOD_INT; A.xtype = CHOLMOD_PATTERN; A.dtype = CHOLMOD_DOUBLE; A.sorted = 1; A.packed = 1;
  cholmod_factor* L = cholmod_analyze_p(&A, (int*)perm.data(), nullptr, 0, &cc);
  lnz = cc.lnz; fl = cc.fl; cholmod_free_factor(&L, &cc); cholmod_finish(&cc);
}
int main(int argc, char** argv) {
  G g = load(argv[1]); string mode = argv[2]; const int seed = atoi(argv[3]);
  vector<int> perm(g.n);
  double t0, t1;
  if (mode == "metis") {
    vector<idx_t> X, A; full(g, X, A);
    idx_t n = g.n, opt[METIS_NOPTIONS]; METIS_SetDefaultOptions(opt); opt[METIS_OPTION_SEED] = seed;
    vector<idx_t> p(n), ip(n);
    t0 = now(); METIS_NodeND(&n, X.data(), A.data(), nullptr, opt, p.data(), ip.data()); t1 = now();
    for (int k = 0; k < n; ++k) perm[k] = p[k];
  } else {
    vector<SCOTCH_Num> X, A; full(g, X, A);
    string strat = argc > 4 ? argv[4] : "";
    int threads = argc > 5 ? atoi(argv[5]) : 1;
    t0 = now();
    SCOTCH_Graph gr; SCOTCH_graphInit(&gr);
    if (SCOTCH_graphBuild(&gr, 0, g.n, X.data(), nullptr, nullptr, nullptr, X[g.n], A.data(), nullptr)) return 4;
    SCOTCH_Strat st; SCOTCH_stratInit(&st);
    if (strat.rfind("flag:", 0) == 0) { if (SCOTCH_stratGraphOrderBuild(&st, atoi(strat.c_str() + 5), 0, 0.2)) return 5; }
    else if (!strat.empty() && SCOTCH_stratGraphOrder(&st, strat.c_str())) return 5;
    vector<SCOTCH_Num> pm(g.n), ip(g.n);
    SCOTCH_Context ctx; SCOTCH_contextInit(&ctx);
    SCOTCH_contextOptionSetNum(&ctx, SCOTCH_OPTIONNUMDETERMINISTIC, 1);
    SCOTCH_contextOptionSetNum(&ctx, SCOTCH_OPTIONNUMRANDOMFIXEDSEED, 1);
    SCOTCH_contextRandomSeed(&ctx, seed);
    if (threads > 1 && SCOTCH_contextThreadSpawn(&ctx, threads, nullptr)) return 6;
    SCOTCH_Graph cg; SCOTCH_graphInit(&cg); SCOTCH_contextBindGraph(&ctx, &gr, &cg);
    const int rc = SCOTCH_graphOrder(&cg, &st, ip.data(), pm.data(), nullptr, nullptr, nullptr);
    SCOTCH_graphExit(&cg); SCOTCH_contextExit(&ctx);
    t1 = now();
    if (rc) return 7;
    // SCOTCH's permtab: old -> new; peritab: new -> old.
    for (int k = 0; k < g.n; ++k) perm[k] = int(pm[k]);
    SCOTCH_stratExit(&st); SCOTCH_graphExit(&gr);
  }
  double lnz, fl; stats(g, perm, lnz, fl);
  printf("%s seed %d n %d time %.3f lnz %.0f flops %.4g\n", mode.c_str(), seed, g.n, t1 - t0, lnz, fl);
}
