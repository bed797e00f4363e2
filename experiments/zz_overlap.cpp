// scratch probe: LAP ordering overlapped with a build in the original numbering, then a symmetric permutation
#include <algorithm>
#include <cstdlib>
#include <thread>
#include <fmt/format.h>
#include "core/timer.h"
#include "harness/thesis_edit.h"
#include "mesh/mesh_io.h"
#include "methods/deformer.h"
#include "methods/normalization.h"
#include "operators/energy_operator.h"
#include "systems/normal_system.h"
#include "systems/vertex_ordering.h"
using namespace db;

// upper CSC, scalar map p (old -> new); returns sorted upper CSC of P A P^T
SpMat symperm_upper(const SpMat& A, const std::vector<int>& p) {
  const int n = int(A.cols());
  std::vector<int> cnt(n + 1, 0);
  const int* Ap = A.outerIndexPtr(); const int* Ai = A.innerIndexPtr(); const double* Ax = A.valuePtr();
  // pass 1: transpose-permute into lower-by-column = rows: build T = (P A P^T) as CSR of upper -> i.e. CSC of lower
  for (int j = 0; j < n; ++j) for (int k = Ap[j]; k < Ap[j + 1]; ++k) { int a = p[Ai[k]], b = p[j]; cnt[std::min(a, b) + 1]++; }
  for (int i = 0; i < n; ++i) cnt[i + 1] += cnt[i];
  // T: column = min (row of upper), entries = max (col of upper)
  std::vector<int> Tp(cnt), Ti(A.nonZeros()); std::vector<double> Tx(A.nonZeros());
  std::vector<int> pos(cnt.begin(), cnt.end() - 1);
  for (int j = 0; j < n; ++j) for (int k = Ap[j]; k < Ap[j + 1]; ++k) { int a = p[Ai[k]], b = p[j]; int r = std::min(a, b), c = std::max(a, b); int q = pos[r]++; Ti[q] = c; Tx[q] = Ax[k]; }
  // pass 2: transpose T back: columns c, rows r ascending (since we scan r ascending)
  std::vector<int> cnt2(n + 1, 0);
  for (std::size_t q = 0; q < Ti.size(); ++q) cnt2[Ti[q] + 1]++;
  for (int i = 0; i < n; ++i) cnt2[i + 1] += cnt2[i];
  SpMat B(n, n); B.resizeNonZeros(A.nonZeros());
  std::copy(cnt2.begin(), cnt2.end(), B.outerIndexPtr());
  std::vector<int> pos2(cnt2.begin(), cnt2.end() - 1);
  for (int r = 0; r < n; ++r) for (int q = Tp[r]; q < Tp[r + 1]; ++q) { int d = pos2[Ti[q]]++; B.innerIndexPtr()[d] = r; B.valuePtr()[d] = Tx[q]; }
  return B;
}

int main(int argc, char** argv) {
  Mesh m = read_mesh(argc > 1 ? argv[1] : "data/generated/armadillo_loop1.off");
  Points Vn = Normalization::fit(m.V).apply(m.V);
  Edit e = harness::make_thesis_edit(m, harness::ThesisEditOptions{});
  for (int rep = 0; rep < 6; ++rep) {
    Adjacency adj = vertex_adjacency(m);
    EnergyOperator op(Vn, m.F, adj, EnergyKind::Lap, EnergyOptions{});
    // sequential (current)
    Timer t;
    Unknowns u1 = make_unknowns(classify(e, ConstraintMode::Soft), 1.0);
    order_unknowns(adj, u1, "amd");
    const double to = t.seconds(); t.reset();
    NormalSystem s1 = build_normal_system(op, u1, Build::Structured);
    const double tb = t.seconds();
    // overlapped
    Timer w;
    Unknowns u0 = make_unknowns(classify(e, ConstraintMode::Soft), 1.0), u2 = u0;
    double tord = 0;
    std::thread th([&] { Timer x; order_unknowns(adj, u2, "amd"); tord = x.seconds(); });
    setenv("DEFORMBENCH_THREADS", "1", 1);
    NormalSystem s0 = build_normal_system(op, u0, Build::Structured);
    unsetenv("DEFORMBENCH_THREADS");
    const double tb0 = w.seconds();
    th.join();
    const double tj = w.seconds();
    Timer tp;
    std::vector<int> p(u0.num_unknowns());
    for (int k = 0; k < u0.num_unknowns(); ++k) p[k] = u2.unknown_of[u0.unknown_vertices[k]];
    SpMat K2 = symperm_upper(s0.K, p);
    const double tpe = tp.seconds();
    const double diff = (SpMat(K2 - s1.K)).norm() / s1.K.norm();
    fmt::print("seq: order {:.3f} + build {:.3f} = {:.3f} | overlap: build1 {:.3f} order {:.3f} joined {:.3f} + perm {:.3f} = {:.3f} | diff {:.2g}\n",
               to, tb, to + tb, tb0, tord, tj, tpe, tj + tpe, diff);
  }
}
