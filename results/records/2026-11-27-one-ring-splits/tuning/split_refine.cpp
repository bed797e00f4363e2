// Scratch study (not part of the build): the first split of the TF 2-ring vertex graph by METIS on the graph
// itself (ufactor 20, as graph_ordering.cpp) against METIS on the 1-ring graph, widened on one side to separate
// the 2-ring graph, then refined on the 2-ring graph by METIS_NodeRefine (one-sided FM, balance bound UB); the
// sides ordered by METIS_NodeND on their 2-ring graphs, the separator last; vertex-level nnz(L) and flops by
// CHOLMOD's analysis. Reads the patterns dumped by ../../2026-11-26-analysis-levers/tuning/dump_pattern.cpp.
//   g++ -O2 -o split_refine split_refine.cpp -I/usr/include/suitesparse -lcholmod -lmetis
//   ./split_refine g104.bin [UB=1.05] [UFACTOR_1RING=20]
#include <metis.h>
#include <cholmod.h>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <vector>
#include <algorithm>
using namespace std;
static double now() { timespec t; clock_gettime(CLOCK_MONOTONIC, &t); return t.tv_sec + 1e-9 * t.tv_nsec; }
struct G { int n; vector<int> p, i; int nv; vector<int> off, nbr, uof; };
G load(const char* f) {
  FILE* F = fopen(f, "rb"); G g; long long nz; fread(&g.n, 4, 1, F); fread(&nz, 8, 1, F);
  g.p.resize(g.n + 1); g.i.resize(nz); fread(g.p.data(), 4, g.n + 1, F); fread(g.i.data(), 4, nz, F);
  long long na; fread(&g.nv, 4, 1, F); fread(&na, 8, 1, F); g.off.resize(g.nv+1); g.nbr.resize(na); g.uof.resize(g.nv);
  fread(g.off.data(),4,g.nv+1,F); fread(g.nbr.data(),4,na,F); fread(g.uof.data(),4,g.nv,F); fclose(F); return g;
}
void full(const G& g, vector<idx_t>& xadj, vector<idx_t>& adj) {
  vector<idx_t> deg(g.n, 0);
  for (int j = 0; j < g.n; ++j) for (int q = g.p[j]; q < g.p[j + 1]; ++q) { int r = g.i[q]; if (r != j) { deg[r]++; deg[j]++; } }
  xadj.assign(g.n + 1, 0); for (int j = 0; j < g.n; ++j) xadj[j + 1] = xadj[j] + deg[j];
  adj.resize(xadj[g.n]); vector<idx_t> pos(xadj.begin(), xadj.end() - 1);
  for (int j = 0; j < g.n; ++j) for (int q = g.p[j]; q < g.p[j + 1]; ++q) { int r = g.i[q]; if (r != j) { adj[pos[r]++] = j; adj[pos[j]++] = r; } }
}
cholmod_sparse view(G& g) {
  cholmod_sparse A{}; A.nrow = A.ncol = g.n; A.nzmax = g.i.size(); A.p = g.p.data(); A.i = g.i.data();
  A.stype = 1; A.itype = CHOLMOD_INT; A.xtype = CHOLMOD_PATTERN; A.dtype = CHOLMOD_DOUBLE; A.sorted = 1; A.packed = 1; return A;
}
void lnz_of(G& g, const vector<int>& perm, cholmod_common& cc, double& lnz, double& fl) {
  cc.nmethods = 1; cc.method[0].ordering = CHOLMOD_GIVEN; cc.postorder = 1; cc.supernodal = CHOLMOD_SIMPLICIAL;
  cholmod_sparse A = view(g);
  cholmod_factor* L = cholmod_analyze_p(&A, (int*)perm.data(), nullptr, 0, &cc);
  lnz = cc.lnz; fl = cc.fl; cholmod_free_factor(&L, &cc);
}
// order: sides by NodeND on induced G2, then separator
vector<int> pipe(const vector<idx_t>& x2, const vector<idx_t>& a2, const vector<idx_t>& part, int n, double& tnd) {
  vector<int> perm; tnd = 0;
  for (int s = 0; s < 2; ++s) {
    vector<int> loc(n, -1), verts; for (int v = 0; v < n; ++v) if (part[v] == s) { loc[v] = verts.size(); verts.push_back(v); }
    vector<idx_t> hx{0}, ha; for (int v : verts) { for (idx_t q = x2[v]; q < x2[v + 1]; ++q) if (loc[a2[q]] >= 0) ha.push_back(loc[a2[q]]); hx.push_back(ha.size()); }
    idx_t m = verts.size(); vector<idx_t> p2(m), ip(m); idx_t o2[METIS_NOPTIONS]; METIS_SetDefaultOptions(o2);
    double c = now(); METIS_NodeND(&m, hx.data(), ha.data(), nullptr, o2, p2.data(), ip.data()); tnd = max(tnd, now() - c);
    for (idx_t k : p2) perm.push_back(verts[k]);
  }
  for (int v = 0; v < n; ++v) if (part[v] == 2) perm.push_back(v);
  return perm;
}
int count(const vector<idx_t>& part, int s) { return std::count(part.begin(), part.end(), s); }
int main(int argc, char** argv) {
  G g = load(argv[1]); double ub = argc > 2 ? atof(argv[2]) : 1.05; int uf1 = argc > 3 ? atoi(argv[3]) : 20;
  cholmod_common cc; cholmod_start(&cc); cc.print = 0;
  vector<idx_t> x2, a2; full(g, x2, a2);
  vector<int> vert(g.n); for (int v=0; v<g.nv; ++v) if (g.uof[v]>=0) vert[g.uof[v]]=v;
  vector<idx_t> x1{0}, a1; for (int u=0;u<g.n;++u){int v=vert[u]; for(int q=g.off[v];q<g.off[v+1];++q){int w=g.uof[g.nbr[q]]; if(w>=0)a1.push_back(w);} x1.push_back(a1.size());}
  idx_t n = g.n; double lnz, fl, tnd;
  {
    idx_t sep; vector<idx_t> part(n); idx_t o[METIS_NOPTIONS]; METIS_SetDefaultOptions(o); o[METIS_OPTION_UFACTOR]=20;
    double t=now(); METIS_ComputeVertexSeparator(&n, x2.data(), a2.data(), nullptr, o, &sep, part.data()); double ts=now()-t;
    auto perm = pipe(x2, a2, part, n, tnd); lnz_of(g, perm, cc, lnz, fl);
    printf("G2 split: %.3f s sides %d %d sep %d | sides ND %.3f | lnz %.0f fl %.4g\n", ts, count(part,0), count(part,1), count(part,2), tnd, lnz, fl);
  }
  {
    idx_t sep; vector<idx_t> part(n); idx_t o[METIS_NOPTIONS]; METIS_SetDefaultOptions(o); o[METIS_OPTION_UFACTOR]=uf1;
    double t=now(); METIS_ComputeVertexSeparator(&n, x1.data(), a1.data(), nullptr, o, &sep, part.data()); double t1=now()-t;
    t=now();
    // widen: side-s endpoints of G2 edges between the sides
    vector<char> conf[2] = {vector<char>(n,0), vector<char>(n,0)};
    int c[2]={0,0};
    for (int v=0; v<n; ++v) if (part[v]<2) for (idx_t q=x2[v]; q<x2[v+1]; ++q) if (part[a2[q]]==1-part[v]) { if(!conf[part[v]][v]) {conf[part[v]][v]=1; c[part[v]]++;} break; }
    int s = c[0] <= c[1] ? 0 : 1;
    for (int v=0; v<n; ++v) if (conf[s][v]) part[v]=2;
    double tw=now()-t;
    int sw = count(part,2);
    t=now(); vector<idx_t> hm(n,-1); METIS_NodeRefine(n, x2.data(), nullptr, a2.data(), part.data(), hm.data(), ub); double tr=now()-t;
    auto perm = pipe(x2, a2, part, n, tnd); lnz_of(g, perm, cc, lnz, fl);
    printf("G1 split + widen + refine(ub %.2f): %.3f + %.3f + %.3f = %.3f s sides %d %d sep %d (widened %d, G1 sep %d) | sides ND %.3f | lnz %.0f fl %.4g\n", ub, t1, tw, tr, t1+tw+tr, count(part,0), count(part,1), count(part,2), sw, (int)sep, tnd, lnz, fl);
  }
}
