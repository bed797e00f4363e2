// Scratch study (not part of the build), on dissect_common.h (as ../../2026-11-27-guided-splits/tuning/seeds.cpp): nested
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
#include <amd.h>
#include "dissect_common.h"
int LEAF = 200;
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
  H h = whole_graph(g);
  for (int seed = s0; seed < s1; ++seed) for (int ring1 = 0; ring1 < 2; ++ring1) {
    SEED = seed; tsplit = 0;
    double t0 = now(); vector<int> perm = dissect(h, L, ring1, 20); double tord = now() - t0;
    cholmod_factor* F = analyze(g, perm, true, cc);
    printf("%s L %d leaf %d seed %d mode %s order_s %.3f split_s %.3f lnz %.0f fl %.5g\n", argv[1], L, LEAF, seed, ring1 ? "ring1" : "ring2", tord, tsplit, cc.lnz, cc.fl);
    fflush(stdout); cholmod_free_factor(&F, &cc);
  }
}
