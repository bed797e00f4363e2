// Shared by draws.cpp and gnd.cpp (scratch studies, not part of the build; first written as
// ../../2026-11-27-guided-splits/tuning/seeds.cpp): the pattern loader of
// ../../2026-11-26-analysis-levers/tuning/dump_pattern.cpp's files, a part's 1-ring and 2-ring graphs, METIS_NodeND
// of a part (timed), the two splits (ring2: METIS's vertex separator of the 2-ring graph; ring1: the guided split of
// graph_ordering.cpp, the 1-ring graph's separator widened on one side and refined on the 2-ring graph), and
// CHOLMOD's analysis of an ordering. Every METIS call takes the seed SEED.
#pragma once
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
struct H { vector<idx_t> x1{0}, a1, x2{0}, a2; vector<int> verts; idx_t n() const { return verts.size(); } };
int SEED; double tsplit = 0;
void opts(idx_t* o) { METIS_SetDefaultOptions(o); o[METIS_OPTION_SEED] = SEED; }
H induced(const H& h, const vector<idx_t>& part, int s) {
  H r; vector<idx_t> loc(h.n(), -1);
  for (idx_t v = 0; v < h.n(); ++v) if (part[v] == s) { loc[v] = r.verts.size(); r.verts.push_back(h.verts[v]); }
  for (idx_t v = 0; v < h.n(); ++v) if (loc[v] >= 0) {
    for (idx_t q = h.x1[v]; q < h.x1[v+1]; ++q) if (loc[h.a1[q]] >= 0) r.a1.push_back(loc[h.a1[q]]);
    r.x1.push_back(r.a1.size());
    for (idx_t q = h.x2[v]; q < h.x2[v+1]; ++q) if (loc[h.a2[q]] >= 0) r.a2.push_back(loc[h.a2[q]]);
    r.x2.push_back(r.a2.size());
  }
  return r;
}
double ndmax = 0, ndsum = 0;  // the parts' METIS_NodeND seconds: slowest, sum
vector<int> nd(H& h) {
  double t0 = now();
  idx_t n = h.n(); vector<idx_t> p(n), ip(n); idx_t o[METIS_NOPTIONS]; opts(o);
  METIS_NodeND(&n, h.x2.data(), h.a2.data(), nullptr, o, p.data(), ip.data());
  { double d = now() - t0; ndmax = max(ndmax, d); ndsum += d; }
  vector<int> r; for (idx_t k : p) r.push_back(h.verts[k]); return r;
}
void split(H& h, bool ring1, idx_t uf, vector<idx_t>& part) {
  idx_t n = h.n(), sep; part.assign(n, 0); idx_t o[METIS_NOPTIONS]; opts(o); o[METIS_OPTION_UFACTOR] = uf;
  double t = now();
  if (!ring1) { METIS_ComputeVertexSeparator(&n, h.x2.data(), h.a2.data(), nullptr, o, &sep, part.data()); tsplit += now() - t; return; }
  METIS_ComputeVertexSeparator(&n, h.x1.data(), h.a1.data(), nullptr, o, &sep, part.data());
  vector<char> conf[2] = {vector<char>(n,0), vector<char>(n,0)}; int c[2] = {0,0};
  for (idx_t v = 0; v < n; ++v) if (part[v] < 2) for (idx_t q = h.x2[v]; q < h.x2[v+1]; ++q) if (part[h.a2[q]] == 1-part[v]) { conf[part[v]][v] = 1; c[part[v]]++; break; }
  int cnt[2] = {0, 0}; for (idx_t v = 0; v < n; ++v) if (part[v] < 2) cnt[part[v]]++;
  int s = c[0] != c[1] ? (c[0] < c[1] ? 0 : 1) : (cnt[0] >= cnt[1] ? 0 : 1);  // as graph_ordering.cpp's widen
  for (idx_t v = 0; v < n; ++v) if (conf[s][v]) part[v] = 2;
  vector<idx_t> hm(n, -1); METIS_NodeRefine(n, h.x2.data(), nullptr, h.a2.data(), part.data(), hm.data(), max(1.05, 1 + uf / 1000.0));
  tsplit += now() - t;
}
//! The whole graph of g: its 2-ring graph from the pattern, its 1-ring graph from the adjacency.
H whole_graph(const G& g) {
  H h; h.verts.resize(g.n); for (int v = 0; v < g.n; ++v) h.verts[v] = v;
  { vector<idx_t> deg(g.n, 0);
    for (int j = 0; j < g.n; ++j) for (int q = g.p[j]; q < g.p[j+1]; ++q) { int r = g.i[q]; if (r != j) { deg[r]++; deg[j]++; } }
    h.x2.assign(g.n+1, 0); for (int j = 0; j < g.n; ++j) h.x2[j+1] = h.x2[j] + deg[j];
    h.a2.resize(h.x2[g.n]); vector<idx_t> pos(h.x2.begin(), h.x2.end()-1);
    for (int j = 0; j < g.n; ++j) for (int q = g.p[j]; q < g.p[j+1]; ++q) { int r = g.i[q]; if (r != j) { h.a2[pos[r]++] = j; h.a2[pos[j]++] = r; } }
    // rows sorted per vertex
    for (int v = 0; v < g.n; ++v) sort(h.a2.begin()+h.x2[v], h.a2.begin()+h.x2[v+1]); }
  vector<int> vert(g.n); for (int v = 0; v < g.nv; ++v) if (g.uof[v] >= 0) vert[g.uof[v]] = v;
  for (int u = 0; u < g.n; ++u) { int v = vert[u]; for (int q = g.off[v]; q < g.off[v+1]; ++q) { int w = g.uof[g.nbr[q]]; if (w >= 0) h.a1.push_back(w); } h.x1.push_back(h.a1.size()); }
  return h;
}
//! CHOLMOD's simplicial analysis of g's pattern under perm (postordered or not).
cholmod_factor* analyze(G& g, vector<int>& perm, bool postorder, cholmod_common& cc) {
  cc.nmethods = 1; cc.method[0].ordering = CHOLMOD_GIVEN; cc.postorder = postorder; cc.supernodal = CHOLMOD_SIMPLICIAL;
  cholmod_sparse A{}; A.nrow = A.ncol = g.n; A.nzmax = g.i.size(); A.p = g.p.data(); A.i = g.i.data();
  A.stype = 1; A.itype = CHOLMOD_INT; A.xtype = CHOLMOD_PATTERN; A.dtype = CHOLMOD_DOUBLE; A.sorted = 1; A.packed = 1;
  return cholmod_analyze_p(&A, perm.data(), nullptr, 0, &cc);
}
