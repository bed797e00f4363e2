// Scratch, not part of the build: nested dissection by METIS separators (METIS_ComputeVertexSeparator) down to
// parts of S vertices, the parts ordered by AMD or by METIS_NodeND; against METIS_NodeND of the whole graph. CPU
// time of the ordering (one thread) and the vertex graph's nnz(L) and flops (CHOLMOD's analysis of the order).
// The graph: the 2-ring pattern dumped by ../../2026-11-26-analysis-levers/tuning/dump_pattern.cpp.
//   g++ -O2 -o nd_leaves nd_leaves.cpp -I/usr/include/suitesparse -lcholmod -lamd -lmetis
//   ./nd_leaves g104.bin nodend            METIS_NodeND of the whole graph
//   ./nd_leaves g104.bin rec S amd|nodend  the separators down to S vertices, the parts by AMD or METIS_NodeND
#include <amd.h>
#include <cholmod.h>
#include <metis.h>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>
using namespace std;
static double now() { timespec t; clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t); return t.tv_sec + 1e-9 * t.tv_nsec; }
struct G { int n; vector<int> p, i; };
G load(const char* f) {
  FILE* F = fopen(f, "rb"); G g; long long nz; fread(&g.n, 4, 1, F); fread(&nz, 8, 1, F);
  g.p.resize(g.n + 1); g.i.resize(nz); fread(g.p.data(), 4, g.n + 1, F); fread(g.i.data(), 4, nz, F); fclose(F); return g;
}
void full(const G& g, vector<idx_t>& xadj, vector<idx_t>& adj) {
  vector<idx_t> deg(g.n, 0);
  for (int j = 0; j < g.n; ++j) for (int q = g.p[j]; q < g.p[j + 1]; ++q) { int r = g.i[q]; if (r != j) { deg[r]++; deg[j]++; } }
  xadj.assign(g.n + 1, 0); for (int j = 0; j < g.n; ++j) xadj[j + 1] = xadj[j] + deg[j];
  adj.resize(xadj[g.n]); vector<idx_t> pos(xadj.begin(), xadj.end() - 1);
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
struct Sub { vector<idx_t> xadj, adj; vector<int> gid; };
Sub induced(const vector<idx_t>& X, const vector<idx_t>& A, const vector<int>& verts, vector<int>& loc) {
  Sub s; s.gid = verts; for (size_t k = 0; k < verts.size(); ++k) loc[verts[k]] = int(k);
  s.xadj.push_back(0);
  for (int v : verts) { for (idx_t q = X[v]; q < X[v + 1]; ++q) if (loc[A[q]] >= 0) s.adj.push_back(loc[A[q]]); s.xadj.push_back(s.adj.size()); }
  for (int v : verts) loc[v] = -1;
  return s;
}
int S_leaf; string leaf; int ufac = 200; double t_sep = 0, t_leaf = 0, t_ind = 0;
void order(const vector<idx_t>& X, const vector<idx_t>& A, const vector<int>& verts, vector<int>& loc, vector<int>& out) {
  double a = now();
  Sub s = induced(X, A, verts, loc);
  t_ind += now() - a;
  idx_t n = verts.size();
  if (n <= S_leaf || s.adj.empty()) {
    a = now();
    vector<idx_t> p(n), ip(n);
    if (leaf == "amd") {
      vector<int> xp(s.xadj.begin(), s.xadj.end()), ai(s.adj.begin(), s.adj.end()), pp(n);
      double ctrl[AMD_CONTROL], info[AMD_INFO]; amd_defaults(ctrl);
      if (ai.empty()) for (int k = 0; k < n; ++k) pp[k] = k; else amd_order(n, xp.data(), ai.data(), pp.data(), ctrl, info);
      for (int k = 0; k < n; ++k) out.push_back(s.gid[pp[k]]);
    } else {
      idx_t opt[METIS_NOPTIONS]; METIS_SetDefaultOptions(opt);
      METIS_NodeND(&n, s.xadj.data(), s.adj.data(), nullptr, opt, p.data(), ip.data());
      for (int k = 0; k < n; ++k) out.push_back(s.gid[p[k]]);
    }
    t_leaf += now() - a;
    return;
  }
  a = now();
  idx_t opt[METIS_NOPTIONS]; METIS_SetDefaultOptions(opt); opt[METIS_OPTION_UFACTOR] = ufac;
  vector<idx_t> part(n); idx_t sepsize = 0;
  METIS_ComputeVertexSeparator(&n, s.xadj.data(), s.adj.data(), nullptr, opt, &sepsize, part.data());
  t_sep += now() - a;
  vector<int> v0, v1, sp;
  for (int k = 0; k < n; ++k) (part[k] == 0 ? v0 : part[k] == 1 ? v1 : sp).push_back(s.gid[k]);
  order(X, A, v0, loc, out); order(X, A, v1, loc, out);
  for (int v : sp) out.push_back(v);
}
int main(int argc, char** argv) {
  G g = load(argv[1]); string mode = argv[2];
  vector<idx_t> X, A; full(g, X, A);
  vector<int> perm;
  double a = now();
  if (mode == "nodend") {
    idx_t n = g.n; vector<idx_t> p(n), ip(n); idx_t opt[METIS_NOPTIONS]; METIS_SetDefaultOptions(opt);
    METIS_NodeND(&n, X.data(), A.data(), nullptr, opt, p.data(), ip.data());
    perm.assign(p.begin(), p.end());
  } else {
    S_leaf = atoi(argv[3]); leaf = argv[4]; if (argc > 5) ufac = atoi(argv[5]);
    vector<int> all(g.n); for (int k = 0; k < g.n; ++k) all[k] = k;
    vector<int> loc(g.n, -1);
    order(X, A, all, loc, perm);
  }
  double t = now() - a;
  double lnz, fl; stats(g, perm, lnz, fl);
  printf("%s %s %s: cpu %.3f (sep %.3f leaf %.3f induced %.3f) lnz %.0f flops %.3g\n", argv[1], mode.c_str(),
         argc > 4 ? (string(argv[3]) + " " + argv[4]).c_str() : "", t, t_sep, t_leaf, t_ind, lnz, fl);
}
