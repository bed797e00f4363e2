#include "harness/budget.h"
#include "systems/vertex_ordering.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "methods/deformer.h"
#include "operators/energy_operator.h"
#include "solvers/linear_solver.h"

namespace db::harness {
namespace {

// Memory the child holds besides the system and the factor: mesh, adjacency, normalized copy, operator weights,
// per-frame buffers (a few hundred bytes per vertex) and the runtime's libraries.
constexpr double kBaseBytes = 16e6, kBytesPerVertex = 400;
// CHOLMOD's supernodal factor stores dense supernode blocks: a little more than nnz(L) values (relaxed
// amalgamation adds explicit zeros, each diagonal block is stored square) plus the row-index lists of the
// supernodes. The multifrontal backend stores only the trapezoids; its count on the vertex graph already
// includes the relaxation's zeros, which differ a little from those of the block graph it analyzes later.
constexpr double kSupernodalSlack = 1.15, kMultifrontalSlack = 1.03;
// Bytes written per second when the dense build zero-fills and copies its matrices.
constexpr double kFillBytesPerSecond = 4e9;

}  // namespace

Prediction DeformPrediction::generic() const {
  Prediction p;
  p.bytes = total_bytes;
  p.seconds = seconds;
  p.basis = basis;
  p.measures = {{"predicted_build_bytes", build_bytes, "bytes"},     {"predicted_factor_bytes", factor_bytes, "bytes"},
                {"predicted_workspace_bytes", workspace_bytes, "bytes"}, {"predicted_bytes", total_bytes, "bytes"},
                {"predicted_factor_nnz", factor_nnz, "count"},        {"predicted_factor_flops", factor_flops, "flop"},
                {"predicted_s", seconds, "s"}};
  return p;
}

CellPredictor::CellPredictor(const Mesh& mesh, const ThesisEditOptions& edit, const MachineRates& rates)
    : mesh_(mesh), rates_(rates) {
  Vn_ = Normalization::fit(mesh.V).apply(mesh.V);
  adj_ = vertex_adjacency(mesh);
  unk_ = make_unknowns(classify(make_thesis_edit(mesh, edit), ConstraintMode::Soft), 1.0);
}

CellPredictor::~CellPredictor() = default;

const EnergyOperator& CellPredictor::op(const std::string& system) {
  auto it = ops_.find(system);
  if (it == ops_.end())
    it = ops_.emplace(system, std::make_unique<EnergyOperator>(Vn_, mesh_.F, adj_, parse_enum<EnergyKind>(system), EnergyOptions{}))
             .first;
  return *it->second;
}

CellPredictor::VertexFactor CellPredictor::vertex_factor(const std::string& backend, const std::string& ordering) {
  const std::string key = backend + "|" + ordering;
  if (auto it = factors_.find(key); it != factors_.end()) return it->second;
  // Upper triangle of the vertex graph of K: unknowns within two edges (the structured build's block pattern).
  const int nu = unk_.num_unknowns();
  InteractionPattern pat = interaction_pattern(adj_, unk_);
  std::vector<int>& colptr = pat.colptr;
  std::vector<int>& rows = pat.rows;
  SpMat P(nu, nu);
  P.resizeNonZeros(static_cast<Eigen::Index>(rows.size()));
  std::copy(colptr.begin(), colptr.end(), P.outerIndexPtr());
  std::copy(rows.begin(), rows.end(), P.innerIndexPtr());
  std::fill(P.valuePtr(), P.valuePtr() + rows.size(), 1.0);  // analyze reads the pattern only
  rows = {};

  VertexFactor f;
  SolverOptions so;
  so.ordering = ordering;
  const std::string family = solver_info(backend).family;
  std::string used = backend;
  if (family != "sparse-cholesky" && family != "sparse-lu") used = "cholmod_supernodal";  // a proxy pattern count
  auto s = make_solver(used, so);
  s->analyze(P);
  FactorStats st = s->stats();
  if (st.nnz_factor == 0 && used != "cholmod_supernodal") {  // backend reports nothing before factorizing
    used = "cholmod_supernodal";
    s = make_solver(used, so);
    s->analyze(P);
    st = s->stats();
  }
  f.backend = used;
  f.nnz = static_cast<double>(st.nnz_factor);
  f.flops = st.flops > 0 ? st.flops : 0;
  f.workspace_bytes = static_cast<double>(st.workspace_bytes);
  f.basis = fmt::format("{} analyze of the {}-vertex 2-ring graph ({} ordering, {} nonzeros in the upper triangle)",
                        used, nu, st.ordering_used, P.nonZeros());
  vertex_nnz_upper_ = static_cast<double>(P.nonZeros());
  factors_[key] = f;
  return f;
}

DeformPrediction CellPredictor::predict(const DeformCell& spec) {
  const Build build = spec.options.build;
  const EnergyOperator& o = op(spec.method());
  const double b = o.block(), r = o.rhs_cols();
  const double nv = mesh_.num_vertices(), nu = b * unk_.num_unknowns(), rows = b * nv;
  DeformPrediction p;
  p.build_bytes = static_cast<double>(predict_build_bytes(o, unk_, build));
  const double base = kBaseBytes + kBytesPerVertex * nv;
  if (build == Build::Dense) {
    // Eigen's LLT of the dense K; predict_build_bytes already counts its copy of K, so it is not added twice.
    p.factor_bytes = nu * nu * 8;
    p.factor_nnz = nu * (nu + 1) / 2;
    p.factor_flops = nu * nu * nu / 3;
    p.build_flops = rows * nu * nu;  // SYRK A^T A
    p.total_bytes = p.build_bytes + base;
    const double frame_flops = 2 * nu * nu * r;
    p.seconds = (p.build_flops + p.factor_flops) / rates_.dense + spec.frames * frame_flops / rates_.stream +
                (rows * nu + 2 * nu * nu) * 8 / kFillBytesPerSecond;
    p.basis = "dense: n^2 doubles, n^3/3 flops";
    return p;
  }
  // Mirror the orderings the deformer ends up with (methods/laplacian_deformer.cpp, solvers/cholmod_solver.cpp):
  // the structured build orders the vertex graph itself (default_vertex_ordering); on the 3x3 block graph of TF,
  // i.e. on the vertex graph, CHOLMOD's default starts from AMD and the multifrontal backend runs METIS; LAP
  // leaves the choice to the backend.
  std::string ordering = spec.options.solver_options.ordering;
  if (ordering == "default")
    ordering = build == Build::Structured ? default_vertex_ordering(b)
               : b > 1                    ? (spec.backend() == "multifrontal" ? "metis" : "amd")
                                          : ordering;
  const VertexFactor vf = vertex_factor(spec.backend(), ordering);
  const double nuv = unk_.num_unknowns();
  // Expand vertex counts to b x b blocks: off-diagonal blocks are full, diagonal blocks lower-triangular.
  p.factor_nnz = b * b * (vf.nnz - nuv) + b * (b + 1) / 2 * nuv;
  p.factor_flops = b * b * b * vf.flops;
  p.factor_bytes = (vf.backend == "multifrontal" ? kMultifrontalSlack : kSupernodalSlack) * 8 * p.factor_nnz + 4 * 6 * nu;
  // Update matrices grow with the square of the front order: b^2 times the vertex graph's.
  p.workspace_bytes = b * b * vf.workspace_bytes;
  // Out of core the factor's values are not resident (a supernode at a time); its row indices are.
  const double resident_factor = spec.factor_storage() == "memory" ? p.factor_bytes : 4 * 6 * nu + 8 * nu;
  p.total_bytes = p.build_bytes + resident_factor + p.workspace_bytes + base;
  const double nnz_k = b * b * (vertex_nnz_upper_ - nuv) + b * (b + 1) / 2 * nuv;
  double stencil = 0;  // sum over row blocks of (#columns)^2: the A^T A product's multiply-adds / b^3
  for (int i = 0; i < mesh_.num_vertices(); ++i) stencil += std::pow(adj_.degree(i) + 1.0, 2);
  p.build_flops = 2 * b * b * b * stencil;
  const double build_factor = build == Build::Naive ? 3.0 : 1.0;  // triplets, transposes, a second product for C
  const double frame_flops = 4 * p.factor_nnz * r + 2 * nnz_k * r;
  p.seconds = build_factor * p.build_flops / rates_.sparse + 30 * nnz_k / rates_.sparse +
              p.factor_flops / rates_.dense + spec.frames * frame_flops / rates_.stream;
  p.basis = vf.basis;
  return p;
}

}  // namespace db::harness
