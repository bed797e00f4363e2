// Scratch study (not part of the build), on dissect_common.h (as ../../2026-11-27-guided-splits/tuning/seeds.cpp): the
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
#include "dissect_common.h"
double seps[8]; vector<char> insep; vector<int> leaf; int nleaf;  // per level; per vertex; the parts
int UF2 = 200, MODE = 2;
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
  if (getenv("UF2")) UF2 = atoi(getenv("UF2"));
  if (getenv("MODE")) MODE = atoi(getenv("MODE"));
  G g = load(argv[1]); int L = atoi(argv[2]); int s0 = atoi(argv[3]), s1 = atoi(argv[4]);
  cholmod_common cc; cholmod_start(&cc); cc.print = 0;
  H h = whole_graph(g);
  for (int seed = s0; seed < s1; ++seed) for (int ring1 = (MODE == 2 ? 0 : MODE); ring1 < (MODE == 2 ? 2 : MODE + 1); ++ring1) {
    ndmax = ndsum = 0;
    SEED = seed; tsplit = 0; for (auto& x: seps) x = 0; insep.assign(g.n, 0); leaf.assign(g.n, -1); nleaf = 0;
    vector<int> perm = dissect(h, L, ring1, 20);
    cholmod_factor* F = analyze(g, perm, false, cc);
    printf("%s L %d seed %d mode %s split_s %.3f lnz %.0f fl %.5g seps", argv[1], L, seed, ring1 ? "ring1" : "ring2",
           tsplit, cc.lnz, cc.fl);
    for (int l = L; l >= 1; --l) printf(" %.0f", seps[l]);
    report_columns(F, g.n);
    fflush(stdout); cholmod_free_factor(&F, &cc);
  }
}
