// Scratch study (not part of the build), an extension of ../../2026-11-27-guided-splits/tuning/seeds.cpp: the
// dissected METIS ordering of an edit's 2-ring vertex pattern over METIS's random draws, its splits computed on the
// 2-ring graph (mode ring2, as graph_ordering.cpp before the guide) or on the 1-ring graph, widened and refined on
// the 2-ring graph (mode ring1, the guided bisect); L levels of splits (the first at ufactor 20, the deeper at
// METIS's 200; parts under 10000 vertices not split), the parts ordered by METIS_NodeND. Every METIS call takes
// the seed `seed`. Prints per seed and mode, besides seeds.cpp's nnz(L) and flops: the separators' vertex counts
// per level (the first split first), the separator columns' share of the flops (top: sum of the squared column
// counts of L over the separators' columns, against all columns; CHOLMOD's unpostordered analysis), and the
// heaviest of the parts against their mean (the same column sums over each part's columns): what a thread
// schedule over the parts starts from; the deeper splits' ufactor (uf2) and the parts' METIS_NodeND wall seconds,
// the slowest (ndmax: the ordering's last step when each part has its own core) and the sum (ndsum).
//   g++ -O2 -o draws draws.cpp -I/usr/include/suitesparse -lcholmod -lmetis
//   [MODE=0|1] [UF2=U] ./draws g104.bin L FIRST_SEED END_SEED
// MODE 0: ring2 only, 1: ring1 only, unset: both; UF2: the ufactor of the splits below the first (default 200).
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
int SEED; double tsplit = 0; double seps[8]; double sep1; vector<char> insep; vector<int> leaf; int nleaf;
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
double ndmax = 0, ndsum = 0; int UF2 = 200; int MODE = 2;
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
vector<int> dissect(H h, int L, bool ring1, idx_t uf) {
  if (L == 0 || h.n() < 10000) { for (int v : h.verts) leaf[v] = nleaf; ++nleaf; return nd(h); }
  vector<idx_t> part; split(h, ring1, uf, part);
  { int c=0; for (auto x: part) c += x==2; seps[L] += c; }
  H a = induced(h, part, 0), b = induced(h, part, 1);
  vector<int> r = dissect(a, L-1, ring1, UF2), rb = dissect(b, L-1, ring1, UF2);
  r.insert(r.end(), rb.begin(), rb.end());
  for (idx_t v = 0; v < h.n(); ++v) if (part[v] == 2) { r.push_back(h.verts[v]); insep[h.verts[v]] = 1; }
  return r;
}
// The separators' and the parts' column sums of L (the squared column counts) under the unpostordered analysis F.
void report_columns(cholmod_factor* F, int n) {
  const int* P = (const int*)F->Perm; const int* C = (const int*)F->ColCount;
  double top = 0, all = 0; vector<double> pf(nleaf, 0);
  for (int k = 0; k < n; ++k) {
    const double c = double(C[k]) * C[k];
    all += c;
    if (insep[P[k]]) top += c;
    if (leaf[P[k]] >= 0) pf[leaf[P[k]]] += c;
  }
  double mx = 0, sm = 0; for (double x : pf) { mx = max(mx, x); sm += x; }
  printf(" topfl %.4g allfl %.4g parts %d partmax/mean %.3f uf2 %d ndmax %.3f ndsum %.3f\n", top, all, nleaf, mx / (sm / nleaf), UF2, ndmax, ndsum);
}
int main(int argc, char** argv) {
  if (getenv("UF2")) UF2 = atoi(getenv("UF2")); if (getenv("MODE")) MODE = atoi(getenv("MODE"));
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
  for (int seed = s0; seed < s1; ++seed) for (int ring1 = (MODE == 2 ? 0 : MODE); ring1 < (MODE == 2 ? 2 : MODE + 1); ++ring1) {
    ndmax = ndsum = 0;
    SEED = seed; tsplit = 0; for (auto& x: seps) x = 0; insep.assign(g.n, 0); leaf.assign(g.n, -1); nleaf = 0;
    vector<int> perm = dissect(h, L, ring1, 20);
    cc.nmethods = 1; cc.method[0].ordering = CHOLMOD_GIVEN; cc.postorder = 0; cc.supernodal = CHOLMOD_SIMPLICIAL;
    cholmod_sparse A{}; A.nrow = A.ncol = g.n; A.nzmax = g.i.size(); A.p = g.p.data(); A.i = g.i.data();
    A.stype = 1; A.itype = CHOLMOD_INT; A.xtype = CHOLMOD_PATTERN; A.dtype = CHOLMOD_DOUBLE; A.sorted = 1; A.packed = 1;
    cholmod_factor* F = cholmod_analyze_p(&A, perm.data(), nullptr, 0, &cc);
    printf("%s L %d seed %d mode %s split_s %.3f lnz %.0f fl %.5g seps", argv[1], L, seed, ring1 ? "ring1" : "ring2",
           tsplit, cc.lnz, cc.fl);
    for (int l = L; l >= 1; --l) printf(" %.0f", seps[l]);
    report_columns(F, g.n);
    fflush(stdout); cholmod_free_factor(&F, &cc);
  }
}
