#include "applications/lse_solve.h"

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "core/timer.h"
#include "methods/deformer.h"
#include "operators/energy_operator.h"

namespace db {
namespace {

// A_u^T delta of the LAP operator: each row i adds coeff_ik delta_i to the unknown of every column k.
DenseMat linear_term(const EnergyOperator& op, const Unknowns& unk, const Points& delta) {
  DenseMat g0 = DenseMat::Zero(unk.num_unknowns(), 3);
  std::vector<int> cols;
  std::vector<double> coeffs;
  for (int i = 0; i < op.num_vertices(); ++i) {
    op.row(i, cols, coeffs);
    for (std::size_t a = 0; a < cols.size(); ++a) {
      const int u = unk.unknown_of[cols[a]];
      if (u >= 0) g0.row(u) += coeffs[a] * delta.row(i);
    }
  }
  return g0;
}

DenseMat rows_of(const Points& P, const std::vector<int>& vertices) {
  DenseMat M(static_cast<Eigen::Index>(vertices.size()), 3);
  for (std::size_t k = 0; k < vertices.size(); ++k) M.row(static_cast<Eigen::Index>(k)) = P.row(vertices[k]);
  return M;
}

}  // namespace

Points uniform_delta(const Mesh& mesh, const Adjacency& adj) {
  return laplacian_coordinates(mesh.V, adj, laplacian_weights(mesh.V, mesh.F, adj, Weights::Uniform));
}

Points solve_lse(const Mesh& mesh, const std::vector<Constraint>& kinds, double soft_weight, const Points& delta,
                 const Points& targets, LseReport* report) {
  const Eigen::Index n = mesh.V.rows();
  if (static_cast<Eigen::Index>(kinds.size()) != n || delta.rows() != n || targets.rows() != n)
    throw InputError(fmt::format("LSE solve: {} vertices but {} constraint kinds, {} Laplacian coordinates and {} "
                                 "targets", n, kinds.size(), delta.rows(), targets.rows()));
  LseReport rep;
  Timer t;
  const Adjacency adj = vertex_adjacency(mesh);
  check_every_component_anchored(adj, kinds);
  const Unknowns unk = make_unknowns(kinds, soft_weight);
  Points x = targets;
  if (unk.num_unknowns() == 0) {
    if (report) *report = rep;
    return x;
  }
  const EnergyOperator op(mesh.V, mesh.F, adj, EnergyKind::Lap, EnergyOptions{});
  NormalSystem sys = build_normal_system(op, unk, Build::Structured);
  sys.g0 = linear_term(op, unk, delta);  // the operator's own target is L(V); ours is delta
  rep.build_s = t.seconds();
  SolverOptions so;
  so.pivot_singularity_test = false;  // anchored (checked above), so regular
  MinQuadWithFixed mq;
  mq.precompute(std::move(sys), unk, "lse", "", so, /*consume_matrix=*/true);
  rep.analyze_s = mq.analyze_seconds();
  rep.factorize_s = mq.factorize_seconds();
  t.reset();
  DenseMat xu;
  mq.form_rhs(rows_of(targets, unk.hard_vertices), rows_of(targets, unk.soft_vertices));
  mq.solve(xu);
  if (!xu.allFinite()) throw SolverError("LSE solve: non-finite positions");
  for (int u = 0; u < unk.num_unknowns(); ++u) x.row(unk.unknown_vertices[u]) = xu.row(u);
  rep.solve_s = t.seconds();
  rep.system = mq.report();
  if (report) *report = rep;
  return x;
}

}  // namespace db
