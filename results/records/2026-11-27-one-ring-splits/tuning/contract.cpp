// Scratch study (not part of the build): METIS_NodeND of the 2-ring vertex graph contracted by LEVELS rounds of
// matching 1-ring neighbours (clusters weighted by size; MAXW caps a cluster's vertices), each cluster's vertices
// consecutive in the expanded order; LEVELS 0: the graph itself. CPU times; vertex-level nnz(L) and flops.
//   g++ -O2 -o contract contract.cpp -I/usr/include/suitesparse -lcholmod -lmetis && ./contract g104.bin LEVELS [MAXW]
#include <cholmod.h>
#include <metis.h>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>
#include <algorithm>
#include <numeric>
using namespace std;
static double now() { timespec t; clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t); return t.tv_sec + 1e-9 * t.tv_nsec; }
struct G { int n; vector<int> p, i; int nv; vector<int> off, nbr, uof; };
G load(const char* f) {
  FILE* F = fopen(f, "rb"); G g; long long nz; fread(&g.n, 4, 1, F); fread(&nz, 8, 1, F);
  g.p.resize(g.n + 1); g.i.resize(nz); fread(g.p.data(), 4, g.n + 1, F); fread(g.i.data(), 4, nz, F);
  long long na; fread(&g.nv, 4, 1, F); fread(&na, 8, 1, F); g.off.resize(g.nv+1); g.nbr.resize(na); g.uof.resize(g.nv);
  fread(g.off.data(),4,g.nv+1,F); fread(g.nbr.data(),4,na,F); fread(g.uof.data(),4,g.nv,F); fclose(F); return g;
}
cholmod_sparse view(G& g) {
  cholmod_sparse A{}; A.nrow = A.ncol = g.n; A.nzmax = g.i.size(); A.p = g.p.data(); A.i = g.i.data();
  A.stype = 1; A.itype = CHOLMOD_INT; A.xtype = CHOLMOD_PATTERN; A.dtype = CHOLMOD_DOUBLE; A.sorted = 1; A.packed = 1; return A;
}
void full(const G& g, vector<idx_t>& xadj, vector<idx_t>& adj) {
  vector<idx_t> deg(g.n, 0);
  for (int j = 0; j < g.n; ++j) for (int q = g.p[j]; q < g.p[j + 1]; ++q) { int r = g.i[q]; if (r != j) { deg[r]++; deg[j]++; } }
  xadj.assign(g.n + 1, 0); for (int j = 0; j < g.n; ++j) xadj[j + 1] = xadj[j] + deg[j];
  adj.resize(xadj[g.n]); vector<idx_t> pos(xadj.begin(), xadj.end() - 1);
  for (int j = 0; j < g.n; ++j) for (int q = g.p[j]; q < g.p[j + 1]; ++q) { int r = g.i[q]; if (r != j) { adj[pos[r]++] = j; adj[pos[j]++] = r; } }
}
void lnz_of(G& g, const vector<int>& perm, cholmod_common& cc, double& lnz, double& fl) {
  cc.nmethods = 1; cc.method[0].ordering = CHOLMOD_GIVEN; cc.postorder = 1; cc.supernodal = CHOLMOD_SIMPLICIAL;
  cholmod_sparse A = view(g);
  cholmod_factor* L = cholmod_analyze_p(&A, (int*)perm.data(), nullptr, 0, &cc);
  lnz = cc.lnz; fl = cc.fl; cholmod_free_factor(&L, &cc);
}
// full graph (xadj, adj) -> 1-ring in unknown numbering
void ring1(const G& g, vector<int>& x1, vector<int>& a1) {
  x1.assign(g.n+1,0); a1.clear();
  vector<int> vert(g.n); for (int v=0; v<g.nv; ++v) if (g.uof[v]>=0) vert[g.uof[v]]=v;
  for (int u=0; u<g.n; ++u) { int v=vert[u]; for (int q=g.off[v]; q<g.off[v+1]; ++q) { int w=g.uof[g.nbr[q]]; if (w>=0) a1.push_back(w);} x1[u+1]=a1.size(); }
}
// matching: cmap[v] = coarse id. mode 0: 1-ring neighbour of min degree; visiting in vertex order
int match(int n, const vector<int>& x, const vector<int>& a, const vector<int>& wgt, vector<int>& cmap, int maxw) {
  cmap.assign(n,-1); int nc=0;
  for (int v=0; v<n; ++v) { if (cmap[v]>=0) continue; int best=-1, bd=1<<30;
    for (int q=x[v]; q<x[v+1]; ++q) { int u=a[q]; if (u==v||cmap[u]>=0||wgt[u]+wgt[v]>maxw) continue; int d=x[u+1]-x[u]; if (d<bd){bd=d;best=u;} }
    cmap[v]=nc; if (best>=0) cmap[best]=nc; ++nc; }
  return nc;
}
// quotient graph of (x,a) under cmap with nc clusters
void quotient(int n, const vector<idx_t>& x, const vector<idx_t>& a, const vector<int>& cmap, int nc, vector<idx_t>& cx, vector<idx_t>& ca) {
  vector<vector<int>> mem(nc); for (int v=0; v<n; ++v) mem[cmap[v]].push_back(v);
  vector<int> mark(nc,-1); cx.assign(nc+1,0); ca.clear();
  for (int c=0; c<nc; ++c) { mark[c]=c; for (int v: mem[c]) for (idx_t q=x[v]; q<x[v+1]; ++q) { int d=cmap[a[q]]; if (mark[d]!=c){mark[d]=c; ca.push_back(d);} } cx[c+1]=ca.size(); }
}
void quotient_i(int n, const vector<int>& x, const vector<int>& a, const vector<int>& cmap, int nc, vector<int>& cx, vector<int>& ca) {
  vector<idx_t> xx(x.begin(),x.end()), aa(a.begin(),a.end()), cxx, caa; quotient(n,xx,aa,cmap,nc,cxx,caa); cx.assign(cxx.begin(),cxx.end()); ca.assign(caa.begin(),caa.end());
}
int main(int argc, char** argv) {
  G g = load(argv[1]); int levels = atoi(argv[2]); int maxw = argc>3? atoi(argv[3]) : 1<<30;
  cholmod_common cc; cholmod_start(&cc); cc.print = 0;
  vector<idx_t> xadj, adj; full(g, xadj, adj);
  double lnz, fl;
  if (levels == 0) {
    idx_t n = g.n; vector<idx_t> p2(n), ip(n); idx_t opt[METIS_NOPTIONS]; METIS_SetDefaultOptions(opt);
    double a = now(); METIS_NodeND(&n, xadj.data(), adj.data(), nullptr, opt, p2.data(), ip.data()); double t=now()-a;
    vector<int> pp(p2.begin(), p2.end()); lnz_of(g, pp, cc, lnz, fl);
    printf("base: n %d edges %zu  nodeND %.3f s  lnz %.0f fl %.3g\n", g.n, adj.size(), t, lnz, fl); return 0;
  }
  double t0=now();
  vector<int> x1, a1; ring1(g, x1, a1);
  vector<int> cmap(g.n); iota(cmap.begin(),cmap.end(),0); int nc=g.n; vector<int> w(g.n,1);
  vector<int> cx1=x1, ca1=a1;
  for (int l=0; l<levels; ++l) {
    vector<int> m; int nc2 = match(nc, cx1, ca1, w, m, maxw);
    vector<int> w2(nc2,0); for (int c=0;c<nc;++c) w2[m[c]]+=w[c];
    vector<int> nx, na; quotient_i(nc, cx1, ca1, m, nc2, nx, na);
    for (int v=0; v<g.n; ++v) cmap[v]=m[cmap[v]];
    cx1=nx; ca1=na; w=w2; nc=nc2;
  }
  double tm=now()-t0; t0=now();
  vector<idx_t> cx, ca; quotient(g.n, xadj, adj, cmap, nc, cx, ca);
  // drop self loops
  { vector<idx_t> nx{0}, na; for (int c=0;c<nc;++c){ for (idx_t q=cx[c];q<cx[c+1];++q) if (ca[q]!=c) na.push_back(ca[q]); nx.push_back(na.size()); } cx=nx; ca=na; }
  double tq=now()-t0;
  idx_t n = nc; vector<idx_t> p2(n), ip(n), vw(w.begin(),w.end()); idx_t opt[METIS_NOPTIONS]; METIS_SetDefaultOptions(opt);
  double a = now(); METIS_NodeND(&n, cx.data(), ca.data(), vw.data(), opt, p2.data(), ip.data()); double t=now()-a;
  vector<vector<int>> mem(nc); for (int v=0; v<g.n; ++v) mem[cmap[v]].push_back(v);
  vector<int> pp; for (idx_t k: p2) for (int v: mem[k]) pp.push_back(v);
  lnz_of(g, pp, cc, lnz, fl);
  printf("levels %d maxw %d: clusters %d edges %zu  match %.3f quotient %.3f nodeND %.3f total %.3f  lnz %.0f fl %.3g\n", levels, maxw, nc, ca.size(), tm, tq, t, tm+tq+t, lnz, fl);
}
