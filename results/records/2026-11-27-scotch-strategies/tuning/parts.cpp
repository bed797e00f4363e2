// Scratch: the project's dissection (first split at ufactor 20, deeper splits at METIS's 200, guided on the 1-ring
// graph from two levels on, parts under 10000 vertices not split) with its parts ordered by METIS_NodeND or by
// SCOTCH under a strategy string: nnz(L), flops, the parts' slowest and summed ordering time.
// The split and the 2-ring and 1-ring graphs come from ../../2026-11-27-guided-splits-16-cores/tuning/dissect_common.h.
// Built and run by parts.sh:  ./parts PATTERN LEVELS SEED nodend|STRATEGY
#include "dissect_common.h"
#include <scotch.h>
#include <string>
string strategy;
double smax = 0, ssum = 0;
vector<int> scotch_order(H& h) {
  double t0 = now();
  const SCOTCH_Num n = h.n();
  vector<SCOTCH_Num> x(h.x2.begin(), h.x2.end()), a(h.a2.begin(), h.a2.end()), pm(n), ip(n);
  SCOTCH_Graph gr; SCOTCH_graphInit(&gr);
  if (SCOTCH_graphBuild(&gr, 0, n, x.data(), nullptr, nullptr, nullptr, x[n], a.data(), nullptr)) exit(4);
  SCOTCH_Strat st; SCOTCH_stratInit(&st);
  if (SCOTCH_stratGraphOrder(&st, strategy.c_str())) exit(5);
  SCOTCH_Context ctx; SCOTCH_contextInit(&ctx);
  SCOTCH_contextOptionSetNum(&ctx, SCOTCH_OPTIONNUMDETERMINISTIC, 1);
  SCOTCH_contextOptionSetNum(&ctx, SCOTCH_OPTIONNUMRANDOMFIXEDSEED, 1);
  SCOTCH_contextRandomSeed(&ctx, SEED < 0 ? 0 : SEED);
  SCOTCH_Graph cg; SCOTCH_graphInit(&cg); SCOTCH_contextBindGraph(&ctx, &gr, &cg);
  if (SCOTCH_graphOrder(&cg, &st, ip.data(), pm.data(), nullptr, nullptr, nullptr)) exit(7);
  SCOTCH_graphExit(&cg); SCOTCH_contextExit(&ctx); SCOTCH_stratExit(&st); SCOTCH_graphExit(&gr);
  { double d = now() - t0; smax = max(smax, d); ssum += d; }
  vector<int> r; for (SCOTCH_Num k : pm) r.push_back(h.verts[k]); return r;
}
vector<int> order_part(H& h) { return strategy == "nodend" ? nd(h) : scotch_order(h); }
vector<int> dissect(H& h, int levels, idx_t uf, bool guided) {
  if (levels == 0 || h.n() < 10000) return order_part(h);
  vector<idx_t> part; split(h, guided, uf, part);
  H s0 = induced(h, part, 0), s1 = induced(h, part, 1);
  vector<int> o = dissect(s0, levels - 1, 200, guided), o1 = dissect(s1, levels - 1, 200, guided);
  o.insert(o.end(), o1.begin(), o1.end());
  for (idx_t v = 0; v < h.n(); ++v) if (part[v] == 2) o.push_back(h.verts[v]);
  return o;
}
int main(int argc, char** argv) {
  G g = load(argv[1]); const int levels = atoi(argv[2]); SEED = atoi(argv[3]); strategy = argv[4];
  H h = whole_graph(g);
  vector<int> perm = dissect(h, levels, 20, levels > 1);
  cholmod_common cc; cholmod_start(&cc); cc.print = 0;
  cholmod_factor* L = analyze(g, perm, true, cc);
  printf("levels %d seed %d parts_max %.3f parts_sum %.3f split %.3f lnz %.0f flops %.5g\n", levels, SEED,
         strategy == "nodend" ? ndmax : smax, strategy == "nodend" ? ndsum : ssum, tsplit, cc.lnz, cc.fl);
  cholmod_free_factor(&L, &cc); cholmod_finish(&cc);
}
