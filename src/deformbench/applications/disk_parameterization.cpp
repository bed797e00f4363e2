#include "applications/disk_parameterization.h"

#include <Eigen/SparseLU>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "solvers/base/error.h"

namespace db {

const EnumText<DiskMap>& enum_text(DiskMap) {
  static const EnumText<DiskMap> t{
      "disk map", {{DiskMap::Uniform, "uniform"}, {DiskMap::MeanValue, "mean-value"}, {DiskMap::Cotangent, "cotangent"}}};
  return t;
}

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

// The slot of neighbour j in i's adjacency list.
int slot(const Adjacency& adj, int i, int j) {
  for (int s = adj.off[i]; s < adj.off[i + 1]; ++s)
    if (adj.nbr[s] == j) return s;
  throw InputError(fmt::format("disk map: vertices {} and {} share a face but no edge", i, j));
}

// w_ij aligned with adj.nbr (see the header), summed face by face from the angle at each corner.
std::vector<double> edge_weights(const Mesh& m, const Adjacency& adj, DiskMap kind) {
  std::vector<double> w(adj.nbr.size(), kind == DiskMap::Uniform ? 1.0 : 0.0);
  if (kind == DiskMap::Uniform) return w;
  for (int f = 0; f < m.num_faces(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int i = m.F(f, c), j = m.F(f, (c + 1) % 3), k = m.F(f, (c + 2) % 3);
      const Vec3 a = m.V.row(j) - m.V.row(i), b = m.V.row(k) - m.V.row(i);
      const double angle = std::atan2(a.cross(b).norm(), a.dot(b));  // at corner i
      if (kind == DiskMap::MeanValue) {
        const double t = std::tan(angle / 2);
        w[slot(adj, i, j)] += t / a.norm();
        w[slot(adj, i, k)] += t / b.norm();
      } else {  // cotangent: the angle at i weighs the opposite edge jk, both ways
        const double ct = 0.5 / std::tan(angle);
        w[slot(adj, j, k)] += ct;
        w[slot(adj, k, j)] += ct;
      }
    }
  for (double x : w)
    if (!std::isfinite(x)) throw InputError(m.name + ": a degenerate triangle gives the disk map infinite weights");
  return w;
}

using Trip = Eigen::Triplet<double, int>;

// Rows sum_j w_ij (u_i - u_j) of the interior vertices, split into the unknowns' columns (k; only the upper
// triangle when `upper`) and the boundary's (c).
void weighted_rows(const Adjacency& adj, const std::vector<double>& w, const Unknowns& unk, bool upper,
                   std::vector<Trip>& k, std::vector<Trip>& c) {
  for (int v : unk.unknown_vertices) {
    const int i = unk.unknown_of[v];
    double diag = 0;
    for (int s = adj.off[v]; s < adj.off[v + 1]; ++s) {
      const int j = unk.unknown_of[adj.nbr[s]];
      diag += w[s];
      if (j < 0) c.emplace_back(i, unk.hard_of[adj.nbr[s]], -w[s]);
      else if (!upper || j > i) k.emplace_back(i, j, -w[s]);
    }
    k.emplace_back(i, i, diag);
  }
}

DenseMat boundary_values(const Unknowns& unk, const UV& uv) {
  DenseMat xh(unk.num_hard(), 2);
  for (int h = 0; h < unk.num_hard(); ++h) xh.row(h) = uv.row(unk.hard_vertices[h]);
  return xh;
}

// Symmetric weights (uniform, cotangent): the Dirichlet energy's normal system through min_quad_with_fixed.
DenseMat solve_symmetric(const Adjacency& adj, const std::vector<double>& w, const Unknowns& unk, const UV& uv,
                         SystemReport* report) {
  std::vector<Trip> k, c;
  weighted_rows(adj, w, unk, /*upper=*/true, k, c);
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
  SolverOptions so;
  so.pivot_singularity_test = false;  // every interior vertex connects to the fixed boundary (one component)
  MinQuadWithFixed mq;
  mq.precompute(std::move(sys), unk, "disk map", "", so, /*consume_matrix=*/true);
  DenseMat xu;
  mq.form_rhs(boundary_values(unk, uv), DenseMat(0, 2));
  mq.solve(xu);
  if (report) *report = mq.report();
  return xu;
}

// Mean-value weights (not symmetric): K u = -C u_boundary by sparse LU.
DenseMat solve_unsymmetric(const Adjacency& adj, const std::vector<double>& w, const Unknowns& unk, const UV& uv) {
  std::vector<Trip> k, c;
  weighted_rows(adj, w, unk, /*upper=*/false, k, c);
  Eigen::SparseMatrix<double> K(unk.num_unknowns(), unk.num_unknowns()), C(unk.num_unknowns(), unk.num_hard());
  K.setFromTriplets(k.begin(), k.end());
  C.setFromTriplets(c.begin(), c.end());
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(K);
  if (lu.info() != Eigen::Success) throw SolverError("disk map: the mean-value system's LU failed: " + lu.lastErrorMessage());
  const DenseMat rhs = -(C * boundary_values(unk, uv));
  DenseMat xu = lu.solve(rhs);
  if (lu.info() != Eigen::Success || !xu.allFinite()) throw SolverError("disk map: the mean-value solve failed");
  return xu;
}

// The interior vertices as the unknowns, the boundary loop's as the fixed ones.
Unknowns interior_unknowns(const DiskPatch& patch) {
  std::vector<Constraint> kinds(static_cast<std::size_t>(patch.num_vertices()), Constraint::Free);
  for (int v : patch.boundary) kinds[static_cast<std::size_t>(v)] = Constraint::Hard;
  return make_unknowns(kinds, 1.0);
}

}  // namespace

Eigen::SparseMatrix<double> disk_map_system(const DiskPatch& patch, DiskMap weights) {
  const Unknowns unk = interior_unknowns(patch);
  const Adjacency adj = vertex_adjacency(patch.mesh);
  std::vector<Trip> k, c;
  weighted_rows(adj, edge_weights(patch.mesh, adj, weights), unk, /*upper=*/false, k, c);
  Eigen::SparseMatrix<double> K(unk.num_unknowns(), unk.num_unknowns());
  K.setFromTriplets(k.begin(), k.end());
  return K;
}

UV disk_parameterization(const DiskPatch& patch, DiskMap weights, SystemReport* report) {
  UV uv = UV::Zero(patch.num_vertices(), 2);
  place_boundary(patch, uv);
  const Unknowns unk = interior_unknowns(patch);
  if (unk.num_unknowns() == 0) return uv;  // every vertex on the boundary: nothing to solve
  const Adjacency adj = vertex_adjacency(patch.mesh);
  const std::vector<double> w = edge_weights(patch.mesh, adj, weights);
  const DenseMat xu = weights == DiskMap::MeanValue ? solve_unsymmetric(adj, w, unk, uv)
                                                    : solve_symmetric(adj, w, unk, uv, report);
  for (int u = 0; u < unk.num_unknowns(); ++u) uv.row(unk.unknown_vertices[u]) = xu.row(u);
  return uv;
}

}  // namespace db
