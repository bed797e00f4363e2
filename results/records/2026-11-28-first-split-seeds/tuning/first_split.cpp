// Scratch study (not part of the build): does the first split's separator size predict the dissected ordering's
// flops? For a mesh (.off, triangles), the 2-ring vertex graph (the soft TF/LAP pattern: every vertex an unknown) is
// dissected as solvers/ordering/graph_ordering.cpp does: L levels (the first split at ufactor 20, deeper at
// METIS's 200; with L > 1, parts over max(n >> L, 5000) split again), guided splits (the 1-ring graph's separator
// widened and refined, dissect_common.h's ring1) when L > 1, the parts ordered by METIS_NodeND. Only the FIRST
// split's METIS seed varies (seed -1 is METIS's default, what the project uses); every other call keeps -1. Prints
// per seed: the first split's separator and sides, its wall seconds, vertex-level nnz(L) and flops (CHOLMOD's
// analysis, postordered).
//   g++ -O2 -o first_split first_split.cpp -I/usr/include/suitesparse -lcholmod -lmetis
//   ./first_split mesh.off L K      (the first split under seeds -1, 1, ..., K-1)
#include <set>
#include "../../2026-11-27-guided-splits-16-cores/tuning/dissect_common.h"

//! The pattern of an .off mesh's 2-ring vertex graph (upper triangle with the diagonal) and its 1-ring adjacency,
//! every vertex an unknown: what dump_pattern.cpp writes for a soft-constraint edit.
G load_off(const char* path) {
  FILE* F = fopen(path, "r");
  char header[16];
  int nf = 0, ne = 0;
  G g;
  if (!F || fscanf(F, "%15s %d %d %d", header, &g.nv, &nf, &ne) != 4) exit((fprintf(stderr, "cannot read %s\n", path), 2));
  for (int v = 0; v < g.nv; ++v) { double x, y, z; if (fscanf(F, "%lf %lf %lf", &x, &y, &z) != 3) exit(2); }
  vector<set<int>> ring(g.nv);
  for (int f = 0; f < nf; ++f) {
    int k, a, b, c;
    if (fscanf(F, "%d %d %d %d", &k, &a, &b, &c) != 4 || k != 3) exit((fprintf(stderr, "not triangles\n"), 2));
    ring[a].insert({b, c}); ring[b].insert({a, c}); ring[c].insert({a, b});
  }
  fclose(F);
  g.n = g.nv;
  g.p = {0}; g.off = {0};
  for (int v = 0; v < g.nv; ++v) {
    set<int> two(ring[v]);
    for (int w : ring[v]) two.insert(ring[w].begin(), ring[w].end());
    for (int w : two) if (w < v) g.i.push_back(w);
    g.i.push_back(v);
    g.p.push_back(g.i.size());
    g.nbr.insert(g.nbr.end(), ring[v].begin(), ring[v].end());
    g.off.push_back(g.nbr.size());
    g.uof.push_back(v);
  }
  return g;
}

idx_t oversize = 0;
vector<int> dissect(H h, int L, bool guided, idx_t uf, int seed) {
  if (!((L > 0 && h.n() >= 10000) || (oversize > 0 && h.n() > oversize))) return nd(h);
  vector<idx_t> part;
  SEED = seed;
  split(h, guided, uf, part);
  SEED = -1;
  H a = induced(h, part, 0), b = induced(h, part, 1);
  vector<int> r = dissect(a, L - 1, guided, 200, -1), rb = dissect(b, L - 1, guided, 200, -1);
  r.insert(r.end(), rb.begin(), rb.end());
  for (idx_t v = 0; v < h.n(); ++v) if (part[v] == 2) r.push_back(h.verts[v]);
  return r;
}

int main(int argc, char** argv) {
  if (argc != 4) return fprintf(stderr, "usage: first_split mesh.off L K\n"), 1;
  G g = load_off(argv[1]);
  const int L = atoi(argv[2]), K = atoi(argv[3]);
  H h = whole_graph(g);
  if (L > 1) oversize = max(g.n >> L, 5000);
  cholmod_common cc;
  cholmod_start(&cc);
  cc.print = 0;
  for (int k = 0; k < K; ++k) {
    const int seed = k == 0 ? -1 : k;
    vector<idx_t> part;
    SEED = seed; tsplit = 0;
    split(h, L > 1, 20, part);
    const double ts = tsplit;
    int c[3] = {0, 0, 0};
    for (idx_t p : part) c[p]++;
    vector<int> perm = dissect(h, L, L > 1, 20, seed);
    cholmod_factor* F = analyze(g, perm, true, cc);
    printf("%s n %d L %d seed %d sep %d sides %d %d split_s %.3f lnz %.0f fl %.6g\n", argv[1], g.n, L, seed, c[2], c[0],
           c[1], ts, cc.lnz, cc.fl);
    fflush(stdout);
    cholmod_free_factor(&F, &cc);
  }
}
