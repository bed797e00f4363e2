// Scratch study (not part of the build): wall time of METIS_ComputeVertexSeparator (ufactor 20) on the 2-ring
// vertex graph against the 1-ring graph of the same unknowns, three times each.
//   g++ -O2 -o split_time split_time.cpp -lmetis && ./split_time g416.bin
#include <metis.h>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <vector>
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
int main(int argc, char** argv) {
  G g = load(argv[1]);
  vector<idx_t> x2, a2; full(g, x2, a2);
  vector<int> vert(g.n); for (int v=0; v<g.nv; ++v) if (g.uof[v]>=0) vert[g.uof[v]]=v;
  vector<idx_t> x1{0}, a1; for (int u=0;u<g.n;++u){int v=vert[u]; for(int q=g.off[v];q<g.off[v+1];++q){int w=g.uof[g.nbr[q]]; if(w>=0)a1.push_back(w);} x1.push_back(a1.size());}
  for (int rep=0; rep<3; ++rep) {
    idx_t n=g.n, sep; vector<idx_t> part(n); idx_t o[METIS_NOPTIONS]; METIS_SetDefaultOptions(o); o[METIS_OPTION_UFACTOR]=20;
    double t=now(); METIS_ComputeVertexSeparator(&n, x2.data(), a2.data(), nullptr, o, &sep, part.data()); double t2=now()-t;
    idx_t sep2; t=now(); METIS_ComputeVertexSeparator(&n, x1.data(), a1.data(), nullptr, o, &sep2, part.data()); double t1=now()-t;
    printf("n %d edges2 %zu edges1 %zu: split G2 %.3f s (sep %d)  split G1 %.3f s (sep %d)\n", g.n, a2.size(), a1.size(), t2, (int)sep, t1, (int)sep2);
  }
}
