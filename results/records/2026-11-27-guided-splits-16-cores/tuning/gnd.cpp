// Scratch study (not part of the build), an extension of ../../2026-11-27-guided-splits/tuning/seeds.cpp: nested
// dissection by guided splits all the way down (the 1-ring graph split by METIS, widened to separate the 2-ring
// graph, refined on it by METIS_NodeRefine; the first split at ufactor 20, the deeper at 200), the parts of at most
// LEAF vertices ordered by AMD on their 2-ring graphs (or by METIS_NodeND with LEAFND set), against METIS_NodeND of
// the whole 2-ring graph (L = 0, LEAF = 0). Every METIS call takes the seed `seed`. Prints per seed: the whole
// ordering's wall seconds (one thread), the splits' share of it, vertex-level nnz(L) and flops by CHOLMOD's
// analysis. Reads the patterns ../../2026-11-26-analysis-levers/tuning/dump_pattern.cpp writes.
//   g++ -O2 -o gnd gnd.cpp -I/usr/include/suitesparse -lcholmod -lmetis -lamd
//   LEAF=0 ./gnd g104.bin 0 SEED SEED+1          METIS_NodeND of the whole graph
//   LEAF=100 [LEAFND=1] ./gnd g104.bin 99 SEED SEED+1   guided dissection to parts of 100 vertices
// (mode ring1 is the guided one; with L = 0 both modes print METIS_NodeND.)
#include <metis.h>
#include <amd.h>
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
int SEED; double tsplit = 0; int LEAF = 200;
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
vector<int> nd(H& h) {
  idx_t n = h.n(); vector<idx_t> p(n), ip(n); idx_t o[METIS_NOPTIONS]; opts(o);
  METIS_NodeND(&n, h.x2.data(), h.a2.data(), nullptr, o, p.data(), ip.data());
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
vector<int> amdo(H& h) {
  int n = h.n(); vector<int> Ap(h.x2.begin(), h.x2.end()), Ai(h.a2.begin(), h.a2.end()), P(n);
  for (int v = 0; v < n; ++v) sort(Ai.begin() + Ap[v], Ai.begin() + Ap[v+1]);
  double Control[AMD_CONTROL], Info[AMD_INFO]; amd_defaults(Control);
  if (amd_order(n, Ap.data(), Ai.data(), P.data(), Control, Info) < 0) abort();
  vector<int> r; for (int k : P) r.push_back(h.verts[k]); return r;
}
vector<int> dissect(H h, int L, bool ring1, idx_t uf) {
  if (h.n() <= LEAF) return getenv("LEAFND") ? nd(h) : amdo(h);
  if (L == 0) return nd(h);
  vector<idx_t> part; split(h, ring1, uf, part);
  H a = induced(h, part, 0), b = induced(h, part, 1);
  vector<int> r = dissect(a, L-1, ring1, 200), rb = dissect(b, L-1, ring1, 200);
  r.insert(r.end(), rb.begin(), rb.end());
  for (idx_t v = 0; v < h.n(); ++v) if (part[v] == 2) r.push_back(h.verts[v]);
  return r;
}
int main(int argc, char** argv) {
  if (getenv("LEAF")) LEAF = atoi(getenv("LEAF"));
  G g = load(argv[1]); int L = atoi(argv[2]); int s0 = atoi(argv[3]), s1 = atoi(argv[4]);
  cholmod_common cc; cholmod_start(&cc); cc.print = 0;
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
  for (int seed = s0; seed < s1; ++seed) for (int ring1 = 0; ring1 < 2; ++ring1) {
    SEED = seed; tsplit = 0;
    double t0 = now(); vector<int> perm = dissect(h, L, ring1, 20); double tord = now() - t0;
    cc.nmethods = 1; cc.method[0].ordering = CHOLMOD_GIVEN; cc.postorder = 1; cc.supernodal = CHOLMOD_SIMPLICIAL;
    cholmod_sparse A{}; A.nrow = A.ncol = g.n; A.nzmax = g.i.size(); A.p = g.p.data(); A.i = g.i.data();
    A.stype = 1; A.itype = CHOLMOD_INT; A.xtype = CHOLMOD_PATTERN; A.dtype = CHOLMOD_DOUBLE; A.sorted = 1; A.packed = 1;
    cholmod_factor* F = cholmod_analyze_p(&A, perm.data(), nullptr, 0, &cc);
    printf("%s L %d leaf %d seed %d mode %s order_s %.3f split_s %.3f lnz %.0f fl %.5g\n", argv[1], L, LEAF, seed, ring1 ? "ring1" : "ring2", tord, tsplit, cc.lnz, cc.fl);
    fflush(stdout); cholmod_free_factor(&F, &cc);
  }
}
