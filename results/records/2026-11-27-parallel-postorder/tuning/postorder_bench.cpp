// Scratch benchmark: the postordering step alone, CHOLMOD's analysis of the whole graph under a dissected order
// (what main 6a986cd ran) against postorder_dissection (solvers/ordering/dissection_postorder.h) on 1 and 2
// threads, on a dumped 2-ring pattern dissected as graph_ordering.cpp does (METIS splits from
// ../../2026-11-27-guided-splits-16-cores/tuning/dissect_common.h, the parts by METIS_NodeND). Checks that the
// two permutations are equal. Built and run by postorder_bench.sh.
//   ./postorder_bench PATTERN LEVELS REPEATS
#include "dissect_common.h"
#include <string>
#include "solvers/ordering/dissection_postorder.h"

vector<db::PositionRange> parts;
bool guided;  // every split on the 1-ring graph, as graph_ordering.cpp from two levels on
vector<int> dissect(H& h, int levels, idx_t uf, int at) {
  if (levels == 0 || h.n() < 10000) { parts.push_back({at, at + int(h.n())}); return nd(h); }
  vector<idx_t> part; split(h, guided, uf, part);
  H s0 = induced(h, part, 0), s1 = induced(h, part, 1);
  vector<int> o = dissect(s0, levels - 1, 200, at);
  vector<int> o1 = dissect(s1, levels - 1, 200, at + int(o.size()));
  o.insert(o.end(), o1.begin(), o1.end());
  for (idx_t v = 0; v < h.n(); ++v) if (part[v] == 2) o.push_back(h.verts[v]);
  return o;
}
double median(vector<double> v) { sort(v.begin(), v.end()); return v[v.size() / 2]; }
int main(int argc, char** argv) {
  G g = load(argv[1]); const int levels = atoi(argv[2]), repeats = atoi(argv[3]); SEED = -1;
  H h = whole_graph(g);
  guided = levels > 1;
  vector<int> order = dissect(h, levels, 20, 0);
  const db::GraphPattern adjacency{g.n, h.x2.data(), h.a2.data()};
  vector<double> tc, t1, t2;
  bool same = true;
  for (int r = 0; r < repeats; ++r) {
    cholmod_common cc; cholmod_start(&cc); cc.print = 0;
    double a = now();
    cholmod_factor* L = analyze(g, order, true, cc);
    tc.push_back(now() - a);
    vector<int> ref((int*)L->Perm, (int*)L->Perm + g.n);
    cholmod_free_factor(&L, &cc); cholmod_finish(&cc);
    for (int threads : {1, 2}) {
      a = now();
      vector<int> p = db::postorder_dissection(adjacency, order, parts, threads);
      (threads == 1 ? t1 : t2).push_back(now() - a);
      same = same && p == ref;
    }
  }
  printf("%s levels %d parts %zu cholmod %.4f dissection_1 %.4f dissection_2 %.4f same %d\n", argv[1], levels,
         parts.size(), median(tc), median(t1), median(t2), int(same));
}
