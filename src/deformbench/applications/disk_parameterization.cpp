#include "applications/disk_parameterization.h"

#include <cmath>
#include <vector>

#include "solvers/base/error.h"

namespace db {
namespace {

// The boundary on the unit circle, angles proportional to the chord length walked from the first vertex.
void place_boundary(const DiskPatch& p, UV& uv) {
  const auto& loop = p.boundary;
  const std::size_t m = loop.size();
  std::vector<double> arc(m + 1, 0.0);
  for (std::size_t k = 0; k < m; ++k)
    arc[k + 1] = arc[k] + (p.mesh.V.row(loop[(k + 1) % m]) - p.mesh.V.row(loop[k])).norm();
  if (!(arc[m] > 0) || !std::isfinite(arc[m]))
    throw InputError(p.mesh.name + ": the patch boundary has zero or non-finite length");
  for (std::size_t k = 0; k < m; ++k) {
    const double t = 2 * M_PI * arc[k] / arc[m];
    uv(loop[k], 0) = std::cos(t);
    uv(loop[k], 1) = std::sin(t);
  }
}

// The graph Laplacian D - A split into unknowns (interior) and hard (boundary) columns: K (upper triangle of its
// interior block) and C (interior rows, boundary columns); g0 = 0 (two columns: u and v).
NormalSystem dirichlet_system(const Adjacency& adj, const Unknowns& unk) {
  using Trip = Eigen::Triplet<double, int>;
  std::vector<Trip> k, c;
  for (int v : unk.unknown_vertices) {
    const int i = unk.unknown_of[v];
    k.emplace_back(i, i, adj.degree(v));
    for (const int* q = adj.begin(v); q != adj.end(v); ++q) {
      const int j = unk.unknown_of[*q];
      if (j < 0) c.emplace_back(i, unk.hard_of[*q], -1.0);
      else if (j > i) k.emplace_back(i, j, -1.0);
    }
  }
  NormalSystem sys;
  sys.build = Build::Structured;
  sys.block = 1;
  sys.rhs_cols = 2;
  sys.K.resize(unk.num_unknowns(), unk.num_unknowns());
  sys.K.setFromTriplets(k.begin(), k.end());
  sys.K.makeCompressed();
  sys.C.resize(unk.num_unknowns(), unk.num_hard());
  sys.C.setFromTriplets(c.begin(), c.end());
  sys.g0.setZero(unk.num_unknowns(), 2);
  return sys;
}

}  // namespace

UV tutte_parameterization(const DiskPatch& patch, SystemReport* report) {
  const int n = patch.num_vertices();
  UV uv = UV::Zero(n, 2);
  place_boundary(patch, uv);
  std::vector<Constraint> kinds(static_cast<std::size_t>(n), Constraint::Free);
  for (int v : patch.boundary) kinds[static_cast<std::size_t>(v)] = Constraint::Hard;
  const Unknowns unk = make_unknowns(kinds, 1.0);
  if (unk.num_unknowns() == 0) return uv;  // every vertex on the boundary: nothing to solve
  const Adjacency adj = vertex_adjacency(patch.mesh);
  SolverOptions so;
  so.pivot_singularity_test = false;  // regular: every interior vertex connects to the fixed boundary (one component)
  MinQuadWithFixed mq;
  mq.precompute(dirichlet_system(adj, unk), unk, "tutte", "", so, /*consume_matrix=*/true);
  DenseMat xh(unk.num_hard(), 2), xu;
  for (int h = 0; h < unk.num_hard(); ++h) xh.row(h) = uv.row(unk.hard_vertices[h]);
  mq.form_rhs(xh, DenseMat(0, 2));
  mq.solve(xu);
  for (int u = 0; u < unk.num_unknowns(); ++u) uv.row(unk.unknown_vertices[u]) = xu.row(u);
  if (report) *report = mq.report();
  return uv;
}

}  // namespace db
