// Scratch study of the METIS levers on a dumped 2-ring pattern (dump_pattern.cpp), not part of the build:
//   g++ -O2 -o metis_levers metis_levers.cpp -I/usr/include/suitesparse -lcholmod -lmetis
//   ./metis_levers g104.bin phases            CPU time of cholmod_metis, cholmod_bisect, the analysis; direct METIS
//   ./metis_levers g104.bin opts niter=2 ...  METIS_NodeND on the whole graph with options; vertex-level lnz
//   ./metis_levers g104.bin pipe UFACTOR      the dissected ordering with the first split at UFACTOR (-2: cholmod_bisect)
//   ./metis_levers g104.bin pipe UFACTOR NITER_SIDES NITER_SPLIT CTYPE_SPLIT   the same with METIS options (-1: default)
#include <cholmod.h>
#include <metis.h>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>
#include <algorithm>
using namespace std;
static double now() { timespec t; clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t); return t.tv_sec + 1e-9 * t.tv_nsec; }
struct G { int n; vector<int> p, i; };  // upper incl diag
G load(const char* f) {
  FILE* F = fopen(f, "rb"); G g; long long nz; fread(&g.n, 4, 1, F); fread(&nz, 8, 1, F);
  g.p.resize(g.n + 1); g.i.resize(nz); fread(g.p.data(), 4, g.n + 1, F); fread(g.i.data(), 4, nz, F); fclose(F); return g;
}
cholmod_sparse view(G& g) {
  cholmod_sparse A{}; A.nrow = A.ncol = g.n; A.nzmax = g.i.size(); A.p = g.p.data(); A.i = g.i.data();
  A.stype = 1; A.itype = CHOLMOD_INT; A.xtype = CHOLMOD_PATTERN; A.dtype = CHOLMOD_DOUBLE; A.sorted = 1; A.packed = 1; return A;
}
// full symmetric adjacency without diagonal
void full(const G& g, vector<idx_t>& xadj, vector<idx_t>& adj) {
  vector<idx_t> deg(g.n, 0);
  for (int j = 0; j < g.n; ++j) for (int q = g.p[j]; q < g.p[j + 1]; ++q) { int r = g.i[q]; if (r != j) { deg[r]++; deg[j]++; } }
  xadj.assign(g.n + 1, 0); for (int j = 0; j < g.n; ++j) xadj[j + 1] = xadj[j] + deg[j];
  adj.resize(xadj[g.n]); vector<idx_t> pos(xadj.begin(), xadj.end() - 1);
  for (int j = 0; j < g.n; ++j) for (int q = g.p[j]; q < g.p[j + 1]; ++q) { int r = g.i[q]; if (r != j) { adj[pos[r]++] = j; adj[pos[j]++] = r; } }
}
double lnz_of(G& g, const vector<int>& perm, cholmod_common& cc) {
  cc.nmethods = 1; cc.method[0].ordering = CHOLMOD_GIVEN; cc.postorder = 1; cc.supernodal = CHOLMOD_SIMPLICIAL;
  cholmod_sparse A = view(g);
  cholmod_factor* L = cholmod_analyze_p(&A, (int*)perm.data(), nullptr, 0, &cc);
  double lnz = cc.lnz; cholmod_free_factor(&L, &cc); return lnz;
}
int main(int argc, char** argv) {
  G g = load(argv[1]);
  cholmod_common cc; cholmod_start(&cc); cc.print = 0;
  string mode = argv[2];
  double t0 = now();
  if (mode == "phases") {
    cholmod_sparse A = view(g);
    vector<int> perm(g.n);
    double a = now(); cholmod_metis(&A, nullptr, 0, 0, perm.data(), &cc); double b = now();
    printf("cholmod_metis whole: %.3f s lnz %.0f\n", b - a, lnz_of(g, perm, cc));
    double c = now(); lnz_of(g, perm, cc); printf("analyze_p given: %.3f s\n", now() - c);
    vector<int> part(g.n); a = now(); cholmod_bisect(&A, nullptr, 0, 1, part.data(), &cc); printf("cholmod_bisect: %.3f s\n", now() - a);
    vector<idx_t> xadj, adj; a = now(); full(g, xadj, adj); printf("full graph: %.3f s\n", now() - a);
    idx_t n = g.n; vector<idx_t> p2(n), ip(n); idx_t opt[METIS_NOPTIONS]; METIS_SetDefaultOptions(opt);
    a = now(); METIS_NodeND(&n, xadj.data(), adj.data(), nullptr, opt, p2.data(), ip.data()); b = now();
    vector<int> pp(p2.begin(), p2.end());
    printf("METIS_NodeND direct default: %.3f s lnz %.0f same_as_cholmod %d\n", b - a, lnz_of(g, pp, cc), int(pp == perm));
  } else if (mode == "pipe") {
    // pipe UFACTOR_TOP [niter for halves]  : ComputeVertexSeparator(whole, ufactor) then NodeND on each side
    int uf = atoi(argv[3]); int nit = argc > 4 ? atoi(argv[4]) : -1;
    vector<idx_t> xadj, adj; full(g, xadj, adj);
    idx_t n = g.n, sepsz; vector<idx_t> part(n); idx_t opt[METIS_NOPTIONS]; METIS_SetDefaultOptions(opt);
    if (uf >= 0) opt[METIS_OPTION_UFACTOR] = uf; if (argc > 5) opt[METIS_OPTION_NITER] = atoi(argv[5]); if (argc > 6) opt[METIS_OPTION_CTYPE] = atoi(argv[6]);
    double a = now();
    if (uf == -2) { cholmod_sparse A = view(g); vector<int> pp(n); cholmod_bisect(&A, nullptr, 0, 1, pp.data(), &cc); part.assign(pp.begin(), pp.end()); }
    else METIS_ComputeVertexSeparator(&n, xadj.data(), adj.data(), nullptr, opt, &sepsz, part.data());
    double tb = now() - a;
    vector<int> perm; double th[2]; int sz[2];
    for (int s = 0; s < 2; ++s) {
      vector<int> loc(n, -1), verts; for (int v = 0; v < n; ++v) if (part[v] == s) { loc[v] = verts.size(); verts.push_back(v); }
      vector<idx_t> hx{0}, ha; for (int v : verts) { for (idx_t q = xadj[v]; q < xadj[v + 1]; ++q) if (loc[adj[q]] >= 0) ha.push_back(loc[adj[q]]); hx.push_back(ha.size()); }
      idx_t m = verts.size(); vector<idx_t> p2(m), ip(m); idx_t o2[METIS_NOPTIONS]; METIS_SetDefaultOptions(o2); if (nit > 0) o2[METIS_OPTION_NITER] = nit;
      double c = now(); METIS_NodeND(&m, hx.data(), ha.data(), nullptr, o2, p2.data(), ip.data()); th[s] = now() - c; sz[s] = m;
      for (idx_t k : p2) perm.push_back(verts[k]);
    }
    for (int v = 0; v < n; ++v) if (part[v] == 2) perm.push_back(v);
    printf("top uf %d niter %d: bisect %.3f sides %d %d sep %d  nodeNDs %.3f %.3f  critical %.3f lnz %.0f\n", uf, nit, tb, sz[0], sz[1], int(n - sz[0] - sz[1]), th[0], th[1], tb + max(th[0], th[1]), lnz_of(g, perm, cc));
  } else if (mode == "opts") {
    // opts: key=value ...
    vector<idx_t> xadj, adj; full(g, xadj, adj);
    idx_t n = g.n; vector<idx_t> p2(n), ip(n); idx_t opt[METIS_NOPTIONS]; METIS_SetDefaultOptions(opt);
    string desc;
    for (int k = 3; k < argc; ++k) {
      string kv = argv[k]; auto e = kv.find('='); string key = kv.substr(0, e); int v = atoi(kv.c_str() + e + 1);
      if (key == "niter") opt[METIS_OPTION_NITER] = v; else if (key == "ctype") opt[METIS_OPTION_CTYPE] = v;
      else if (key == "rtype") opt[METIS_OPTION_RTYPE] = v; else if (key == "nseps") opt[METIS_OPTION_NSEPS] = v;
      else if (key == "ufactor") opt[METIS_OPTION_UFACTOR] = v; else if (key == "compress") opt[METIS_OPTION_COMPRESS] = v;
      else if (key == "ccorder") opt[METIS_OPTION_CCORDER] = v; else if (key == "pfactor") opt[METIS_OPTION_PFACTOR] = v;
      else if (key == "seed") opt[METIS_OPTION_SEED] = v; else if (key == "no2hop") opt[METIS_OPTION_NO2HOP] = v;
      else if (key == "iptype") opt[METIS_OPTION_IPTYPE] = v;
      else { fprintf(stderr, "bad %s\n", key.c_str()); return 1; }
      desc += kv + " ";
    }
    double best = 1e9; vector<int> pp;
    for (int rep = 0; rep < 3; ++rep) {
      double a = now(); METIS_NodeND(&n, xadj.data(), adj.data(), nullptr, opt, p2.data(), ip.data()); best = min(best, now() - a);
    }
    pp.assign(p2.begin(), p2.end());
    printf("%-40s cpu %.3f s lnz %.0f\n", desc.c_str(), best, lnz_of(g, pp, cc));
  }
  cholmod_finish(&cc);
}
