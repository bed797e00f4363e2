#include "harness/budget.h"
#include "systems/vertex_ordering.h"

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "methods/deformer.h"
#include "operators/energy_operator.h"

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

// K's vertex graph in the mesh's vertex order, ordered by the backend with `ordering`.
const FactorCount& CellPredictor::factor(const DeformCell& cell, int block, const std::string& ordering) {
  const std::string key = fmt::format("{}|{}|{}", cell.backend(), ordering, block);
  if (auto it = factors_.find(key); it != factors_.end()) return it->second;
  DeformOptions o = cell.options;
  o.solver_options.ordering = ordering;
  const FactorCount f = count_factor(interaction_pattern(adj_, unk_), unk_.num_unknowns(), false, block, o, true);
  return factors_.emplace(key, f).first->second;
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
  const FactorCount& f = factor(spec, int(b), ordering);
  p.factor_nnz = f.nnz;
  p.factor_flops = f.flops;
  p.factor_bytes = (f.backend == "multifrontal" ? kMultifrontalSlack : kSupernodalSlack) * 8 * p.factor_nnz + 4 * 6 * nu;
  p.workspace_bytes = f.workspace;
  // Out of core the factor's values are not resident (a supernode at a time); its row indices are.
  const double resident_factor = spec.factor_storage() == "memory" ? p.factor_bytes : 4 * 6 * nu + 8 * nu;
  p.total_bytes = p.build_bytes + resident_factor + p.workspace_bytes + base;
  const double nnz_k = f.nnz_matrix;
  p.build_flops = stencil_flops(adj_, mesh_.num_vertices(), int(b));
  const double build_factor = build == Build::Naive ? 3.0 : 1.0;  // triplets, transposes, a second product for C
  const double frame_flops = 4 * p.factor_nnz * r + 2 * nnz_k * r;
  p.seconds = build_factor * p.build_flops / rates_.sparse + 30 * nnz_k / rates_.sparse +
              p.factor_flops / rates_.dense + spec.frames * frame_flops / rates_.stream;
  p.basis = f.basis;
  return p;
}

}  // namespace db::harness
