// Scratch study of cheaper orderings of the 2-ring graph (issue 31, the 2-core analysis target), not part of the
// build. Reads the pattern dumped by ../../2026-11-26-analysis-levers/tuning/dump_pattern.cpp (g26.bin, g104.bin,
// g416.bin from the armadillo_whole, _loop1_whole and _loop2_whole edits). Vertex-level nnz(L) and flops from
// CHOLMOD's simplicial analysis under the computed order.
//   g++ -O2 -o study study.cpp -I/usr/include/suitesparse -lcholmod -lmetis -lamd
//   ./study g104.bin base                 METIS_NodeND on the whole graph: CPU s, nnz(L), flops
//   ./study g104.bin rep 5                the same 5 times in one process: CPU s and page faults of each call
//   ./study g104.bin coarse LEVELS g1|g2  METIS on the graph coarsened by LEVELS matchings (of the 1- or 2-ring graph)
//   ./study g104.bin dis UFACTOR          the project's dissection: a METIS separator at UFACTOR, sides by NodeND
//   ./study g104.bin g1 UFACTOR           the same with the separator computed on the 1-ring graph and widened
//   ./study g104.bin rec LEAF amd|metis   METIS separators down to parts below LEAF vertices, ordered by AMD or METIS
//   UF2=200 ./study g104.bin depth D U    D levels of separators (the first at ufactor U, deeper at UF2), NodeND below
//   ./study g104.bin crit D               the project's D-level dissection (first split at ufactor 20, deeper at METIS's
//                                         own, parts under 10000 vertices whole): CPU total and critical path
#include <cholmod.h>
#include <metis.h>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>
#include <algorithm>
#include <sys/resource.h>
using namespace std;
static double cpu() { timespec t; clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t); return t.tv_sec + 1e-9 * t.tv_nsec; }
struct G { int n; vector<int> p, i; int nv; vector<int> off, nbr, uof; };
G load(const char* f) {
  FILE* F = fopen(f, "rb"); G g; long long nz; fread(&g.n, 4, 1, F); fread(&nz, 8, 1, F);
  g.p.resize(g.n + 1); g.i.resize(nz); fread(g.p.data(), 4, g.n + 1, F); fread(g.i.data(), 4, nz, F);
  long long na; fread(&g.nv, 4, 1, F); fread(&na, 8, 1, F); g.off.resize(g.nv+1); g.nbr.resize(na);
  fread(g.off.data(),4,g.nv+1,F); fread(g.nbr.data(),4,na,F); g.uof.resize(g.nv); fread(g.uof.data(),4,g.nv,F); fclose(F); return g;
}
// full adjacency of G^2 without diag
void full(const G& g, vector<idx_t>& xadj, vector<idx_t>& adj) {
  vector<idx_t> deg(g.n, 0);
  for (int j = 0; j < g.n; ++j) for (int q = g.p[j]; q < g.p[j+1]; ++q) if (g.i[q] < j) deg[g.i[q]]++, deg[j]++;
  xadj.assign(g.n+1,0); for (int j=0;j<g.n;++j) xadj[j+1]=xadj[j]+deg[j];
  adj.resize(xadj[g.n]); vector<idx_t> nx(xadj.begin(), xadj.end()-1);
  for (int j = 0; j < g.n; ++j) for (int q = g.p[j]; q < g.p[j+1]; ++q) if (int r=g.i[q]; r < j) adj[nx[j]++]=r, adj[nx[r]++]=j;
}
pair<double,double> fill(G& g, const vector<int>& perm) {
  cholmod_common cc; cholmod_start(&cc); cc.print=0; cc.supernodal=CHOLMOD_SIMPLICIAL; cc.nmethods=1; cc.method[0].ordering=CHOLMOD_GIVEN; cc.postorder=1;
  cholmod_sparse A{}; A.nrow=A.ncol=g.n; A.nzmax=g.i.size(); A.p=g.p.data(); A.i=g.i.data(); A.stype=1; A.itype=CHOLMOD_INT; A.xtype=CHOLMOD_PATTERN; A.dtype=CHOLMOD_DOUBLE; A.sorted=1; A.packed=1;
  cholmod_factor* L = cholmod_analyze_p(&A, (int*)perm.data(), nullptr, 0, &cc);
  double lnz=0, fl=0; int* cc_=(int*)L->ColCount; for (int j=0;j<g.n;++j){ lnz+=cc_[j]; fl+= double(cc_[j])*cc_[j]; }
  cholmod_free_factor(&L,&cc); cholmod_finish(&cc); return {lnz, fl};
}
vector<int> nodend(vector<idx_t>& xadj, vector<idx_t>& adj, vector<idx_t>* vw, int n) {
  idx_t nn=n; vector<idx_t> perm(n), iperm(n); idx_t opt[METIS_NOPTIONS]; METIS_SetDefaultOptions(opt);
  METIS_NodeND(&nn, xadj.data(), adj.data(), vw?vw->data():nullptr, opt, perm.data(), iperm.data());
  return vector<int>(perm.begin(), perm.end());
}
// matching on 1-ring graph: SHEM-like: visit vertices by ascending degree, match with unmatched neighbour of min degree
vector<int> match1(const G& g, const vector<int>& cmap_in, int nin, int& nc, const vector<int>& xo, const vector<int>& no) {
  // generic on graph (xo,no) over nin vertices
  vector<int> deg(nin); for(int v=0;v<nin;++v) deg[v]=xo[v+1]-xo[v];
  vector<int> ord(nin); for(int v=0;v<nin;++v) ord[v]=v; stable_sort(ord.begin(),ord.end(),[&](int a,int b){return deg[a]<deg[b];});
  vector<int> m(nin,-1); nc=0; vector<int> cmap(nin);
  for(int v:ord){ if(m[v]>=0) continue; int best=-1; for(int q=xo[v];q<xo[v+1];++q){int u=no[q]; if(m[u]<0&&u!=v&&(best<0||deg[u]<deg[best])) best=u;} 
    if(best<0){m[v]=v; cmap[v]=nc++;} else {m[v]=best;m[best]=v; cmap[v]=cmap[best]=nc++;} }
  return cmap;
}

// induced subgraph of full graph (xadj,adj) on vertices with part==w
void induced(const vector<idx_t>& xadj,const vector<idx_t>& adj,const vector<idx_t>& part,int w, vector<idx_t>& hx, vector<idx_t>& ha, vector<int>& verts){
  int n=xadj.size()-1; vector<int> loc(n,-1); verts.clear(); for(int v=0;v<n;++v) if(part[v]==w){loc[v]=verts.size(); verts.push_back(v);} 
  hx.assign(1,0); ha.clear(); for(int v:verts){ for(idx_t q=xadj[v];q<xadj[v+1];++q) if(loc[adj[q]]>=0) ha.push_back(loc[adj[q]]); hx.push_back(ha.size()); }
}
vector<int> sides_order(vector<idx_t>& xadj, vector<idx_t>& adj, vector<idx_t>& part, double& tsides, double& tmax){
  vector<int> perm; tsides=0; tmax=0;
  for(int w=0;w<2;++w){ vector<idx_t> hx,ha; vector<int> verts; induced(xadj,adj,part,w,hx,ha,verts); double t=cpu(); auto o=nodend(hx,ha,nullptr,verts.size()); t=cpu()-t; tsides+=t; tmax=max(tmax,t); for(int k:o) perm.push_back(verts[k]); }
  for(int v=0;v<(int)part.size();++v) if(part[v]==2) perm.push_back(v);
  return perm;
}
int separator(vector<idx_t>& xadj, vector<idx_t>& adj, vector<idx_t>& part, int uf){
  idx_t n=xadj.size()-1, sep; part.assign(n,0); idx_t opt[METIS_NOPTIONS]; METIS_SetDefaultOptions(opt); opt[METIS_OPTION_UFACTOR]=uf;
  METIS_ComputeVertexSeparator(&n,xadj.data(),adj.data(),nullptr,opt,&sep,part.data()); return sep;
}

#include <amd.h>
int UF=200;
void rec(vector<idx_t>& xadj, vector<idx_t>& adj, const vector<int>& verts, int leaf, vector<int>& out, const string& lm){
  int n=verts.size();
  if(n<leaf || leaf < 0){ 
    if(lm=="amd"){ vector<int> P(n); vector<int> Ap(xadj.begin(),xadj.end()), Ai(adj.begin(),adj.end()); double ctl[AMD_CONTROL], info[AMD_INFO]; amd_defaults(ctl);
      if(n>0) amd_order(n,Ap.data(),Ai.data(),P.data(),ctl,info); for(int k:P) out.push_back(verts[k]); }
    else { auto o=nodend(xadj,adj,nullptr,n); for(int k:o) out.push_back(verts[k]); }
    return; }
  vector<idx_t> part; separator(xadj,adj,part,UF);
  int nl = leaf > 0 ? leaf : leaf + 1;  // leaf <= 0: -depth
  for(int w=0;w<2;++w){ vector<idx_t> hx,ha; vector<int> vv; induced(xadj,adj,part,w,hx,ha,vv); vector<int> gv(vv.size()); for(size_t k=0;k<vv.size();++k) gv[k]=verts[vv[k]]; rec(hx,ha,gv,leaf>0?leaf:nl,out,lm); }
  for(int v=0;v<n;++v) if(part[v]==2) out.push_back(verts[v]);
}

void recd(vector<idx_t>& xadj, vector<idx_t>& adj, const vector<int>& verts, int depth, vector<int>& out, int uf){
  int n=verts.size();
  if(depth==0){ auto o=nodend(xadj,adj,nullptr,n); for(int k:o) out.push_back(verts[k]); return; }
  vector<idx_t> part; separator(xadj,adj,part,uf);
  int uf2 = getenv("UF2") ? atoi(getenv("UF2")) : uf;
  for(int w=0;w<2;++w){ vector<idx_t> hx,ha; vector<int> vv; induced(xadj,adj,part,w,hx,ha,vv); vector<int> gv(vv.size()); for(size_t k=0;k<vv.size();++k) gv[k]=verts[vv[k]]; recd(hx,ha,gv,depth-1,out,uf2); }
  for(int v=0;v<n;++v) if(part[v]==2) out.push_back(verts[v]);
}

// As recd, with the project's rule (parts under 10000 vertices not split) and the CPU time of each node: returns
// the critical path (a split, then the longer of its two sides), the total in `total`.
double recc(vector<idx_t>& xadj, vector<idx_t>& adj, const vector<int>& verts, int depth, vector<int>& out, int uf, double& total){
  int n=verts.size();
  double t0=cpu();
  if(depth==0 || n<10000){ auto o=nodend(xadj,adj,nullptr,n); for(int k:o) out.push_back(verts[k]); double t=cpu()-t0; total+=t; return t; }
  vector<idx_t> part; separator(xadj,adj,part,uf);
  vector<idx_t> hx[2],ha[2]; vector<int> gv[2];
  for(int w=0;w<2;++w){ vector<int> vv; induced(xadj,adj,part,w,hx[w],ha[w],vv); gv[w].resize(vv.size()); for(size_t k=0;k<vv.size();++k) gv[w][k]=verts[vv[k]]; }
  double split=cpu()-t0; total+=split;
  double c[2]; for(int w=0;w<2;++w) c[w]=recc(hx[w],ha[w],gv[w],depth-1,out,200,total);
  for(int v=0;v<n;++v) if(part[v]==2) out.push_back(verts[v]);
  return split+max(c[0],c[1]);
}
int main(int argc, char** argv) {
  G g = load(argv[1]); string mode = argv[2];
  vector<idx_t> xadj, adj; full(g, xadj, adj);
  // 1-ring graph over unknowns (all vertices unknown assumed)
  vector<int> x1(g.nv+1,0), n1; for(int v=0;v<g.nv;++v){ for(int q=g.off[v];q<g.off[v+1];++q) n1.push_back(g.nbr[q]); x1[v+1]=n1.size(); }
  if (mode=="rep") { for(int k=0;k<atoi(argv[3]);++k){ rusage r0,r1; getrusage(RUSAGE_SELF,&r0); double t=cpu(); auto perm=nodend(xadj,adj,nullptr,g.n); t=cpu()-t; getrusage(RUSAGE_SELF,&r1);
     printf("rep cpu %.3f minflt %ld sys %.3f\n",t,r1.ru_minflt-r0.ru_minflt,(r1.ru_stime.tv_sec-r0.ru_stime.tv_sec)+1e-6*(r1.ru_stime.tv_usec-r0.ru_stime.tv_usec)); } return 0; }
  if (mode=="dis") { int uf=atoi(argv[3]); double t=cpu(); vector<idx_t> part; separator(xadj,adj,part,uf); t=cpu()-t; double ts,tm; auto perm=sides_order(xadj,adj,part,ts,tm);
     int c[3]={0,0,0}; for(auto p:part) c[p]++; auto f=fill(g,perm); printf("dis uf %d split %.3f sides %.3f max %.3f | %d %d %d lnz %.0f flops %.4g\n",uf,t,ts,tm,c[0],c[1],c[2],f.first,f.second); return 0; }
  if (mode=="g1") { int uf=atoi(argv[3]); vector<idx_t> X1(x1.begin(),x1.end()), N1(n1.begin(),n1.end()); double t=cpu(); vector<idx_t> part; separator(X1,N1,part,uf);
     // widen: vertices of side s with a G^2 neighbour on the other side (all vertices unknown here -> G^2 adjacency = adj)
     int c[3]={0,0,0}; for(auto p:part) c[p]++;
     vector<int> w[2]; for(int v=0;v<g.n;++v) if(part[v]<2){ for(idx_t q=xadj[v];q<xadj[v+1];++q) if(part[adj[q]]==1-part[v]){ w[part[v]].push_back(v); break; } }
     int s0 = w[0].size()!=w[1].size() ? (w[0].size()<w[1].size()?0:1) : (c[0]>=c[1]?0:1);
     for(int v:w[s0]) part[v]=2;
     // thin: separator vertices that reach only one side in G^2
     for(int v=0;v<g.n;++v) if(part[v]==2){ bool r[3]={0,0,0}; for(idx_t q=xadj[v];q<xadj[v+1];++q) r[part[adj[q]]]=1; if(r[0]&&r[1]) continue; int c2[3]={0,0,0}; for(int u=0;u<g.n;++u); part[v]= r[0]?0: r[1]?1:0; }
     t=cpu()-t; double ts,tm; auto perm=sides_order(xadj,adj,part,ts,tm);
     int cc[3]={0,0,0}; for(auto p:part) cc[p]++; auto f=fill(g,perm); printf("g1 uf %d split %.3f sides %.3f max %.3f | %d %d %d lnz %.0f flops %.4g\n",uf,t,ts,tm,cc[0],cc[1],cc[2],f.first,f.second); return 0; }
  if (mode=="rec") { int leaf=atoi(argv[3]); string lm=argv[4]; if(argc>5) UF=atoi(argv[5]); vector<int> verts(g.n); for(int v=0;v<g.n;++v) verts[v]=v; vector<int> perm; double t=cpu(); rec(xadj,adj,verts,leaf,perm,lm); t=cpu()-t; auto f=fill(g,perm);
     printf("rec leaf %d %s cpu %.3f lnz %.0f flops %.4g\n",leaf,lm.c_str(),t,f.first,f.second); return 0; }
  if (mode=="depth") { int d=atoi(argv[3]); int uf=atoi(argv[4]); vector<int> verts(g.n); for(int v=0;v<g.n;++v) verts[v]=v; vector<int> perm; double t=cpu(); recd(xadj,adj,verts,d,perm,uf); t=cpu()-t; auto f=fill(g,perm);
     printf("depth %d uf %d cpu %.3f lnz %.0f flops %.4g\n",d,uf,t,f.first,f.second); return 0; }
  if (mode=="crit") { int d=atoi(argv[3]); vector<int> verts(g.n); for(int v=0;v<g.n;++v) verts[v]=v; vector<int> perm; double total=0; double crit=recc(xadj,adj,verts,d,perm,20,total); auto f=fill(g,perm);
     printf("levels %d: CPU total %.3f, critical path %.3f, lnz %.0f flops %.4g\n",d,total,crit,f.first,f.second); return 0; }
  if (mode=="base") {
    double t=cpu(); auto perm=nodend(xadj,adj,nullptr,g.n); t=cpu()-t; auto f=fill(g,perm); printf("base cpu %.3f lnz %.0f flops %.4g\n",t,f.first,f.second); return 0; }
  int levels = atoi(argv[3]); const char* on = argc>4?argv[4]:"g1";
  double t=cpu();
  // clusters: cmap from vertices to cluster, via repeated matching
  vector<int> cmap(g.n); for(int v=0;v<g.n;++v) cmap[v]=v; int nc=g.n;
  vector<int> xo = string(on)=="g1"? x1 : vector<int>(xadj.begin(),xadj.end()); vector<int> no = string(on)=="g1"? n1 : vector<int>(adj.begin(),adj.end());
  for(int l=0;l<levels;++l){ int nn; vector<int> cm=match1(g,cmap,nc,nn,xo,no);
    // contract graph (xo,no)
    vector<vector<int>> nb(nn); for(int v=0;v<nc;++v) for(int q=xo[v];q<xo[v+1];++q){int a=cm[v],b=cm[no[q]]; if(a!=b) nb[a].push_back(b);} 
    vector<int> x2(nn+1,0), n2; for(int a=0;a<nn;++a){ auto& L=nb[a]; sort(L.begin(),L.end()); L.erase(unique(L.begin(),L.end()),L.end()); n2.insert(n2.end(),L.begin(),L.end()); x2[a+1]=n2.size(); }
    for(int v=0;v<g.n;++v) cmap[v]=cm[cmap[v]]; nc=nn; xo=x2; no=n2; }
  // quotient of G^2
  vector<vector<int>> nb(nc); vector<idx_t> vw(nc,0); for(int v=0;v<g.n;++v) vw[cmap[v]]++;
  for(int v=0;v<g.n;++v) for(idx_t q=xadj[v];q<xadj[v+1];++q){int a=cmap[v],b=cmap[adj[q]]; if(a!=b) nb[a].push_back(b);} 
  vector<idx_t> hx(nc+1,0), ha; for(int a=0;a<nc;++a){auto& L=nb[a]; sort(L.begin(),L.end()); L.erase(unique(L.begin(),L.end()),L.end()); ha.insert(ha.end(),L.begin(),L.end()); hx[a+1]=ha.size();}
  double tc=cpu()-t;
  auto cp = nodend(hx,ha,&vw,nc);
  // expand
  vector<vector<int>> mem(nc); for(int v=0;v<g.n;++v) mem[cmap[v]].push_back(v);
  vector<int> perm; for(int a:cp) for(int v:mem[a]) perm.push_back(v);
  t=cpu()-t; auto f=fill(g,perm);
  printf("coarse L%d on %s: nc %d edges %zu contract %.3f total cpu %.3f lnz %.0f flops %.4g\n",levels,on,nc,ha.size(),tc,t,f.first,f.second);
}
