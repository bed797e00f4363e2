#pragma once
//! Predicting a cell's memory and time before it is allowed to run (thesis Table 2-1 marks the cells that did
//! not fit its 1 GB machine "#over"; here a cell over budget is never attempted and keeps its prediction).
//!
//! Memory: predict_build_bytes (systems/normal_system.h, from the adjacency alone) + the factor: dense n^2 * 8,
//! sparse from the backend's symbolic analysis of K's 2-ring vertex graph, expanded to 3x3 blocks for TF
//! (count_factor, methods/run_prediction.h: the analysis `deformbench deform` and `advise` predict with).
//! Time: flop counts over rates measured once per run (a dense GEMM, a sparse A^T A product).
#include <map>
#include <memory>
#include <string>

#include "harness/deform_cell.h"
#include "harness/machine_rates.h"
#include "harness/runner.h"
#include "mesh/mesh.h"
#include "methods/normalization.h"
#include "methods/run_prediction.h"
#include "systems/normal_system.h"

namespace db::harness {

//! What a deformation cell was predicted to need before it was allowed to run.
struct DeformPrediction {
  double build_bytes = 0;   //!< predict_build_bytes (dense: includes the LLT's copy of K)
  double factor_bytes = 0;  //!< dense: n^2 * 8; sparse: from a symbolic analysis of the vertex graph
  double workspace_bytes = 0;  //!< the factorization's working storage besides the factor (update matrices)
  double total_bytes = 0;   //!< what the memory budget is checked against
  double factor_nnz = 0, factor_flops = 0, build_flops = 0;
  double seconds = 0;       //!< what the time budget is checked against (build + analyze + factor + frames)
  std::string basis;        //!< how the factor was predicted, for the raw cell records
  //! For the runner: bytes, seconds and the measures predicted_build_bytes, predicted_factor_bytes,
  //! predicted_workspace_bytes, predicted_bytes, predicted_factor_nnz, predicted_factor_flops, predicted_s.
  Prediction generic() const;
};

//! Predicts every cell of one mesh under the thesis edit. Holds the mesh's adjacency and operators, and caches
//! the vertex-graph factor analysis per (backend, ordering, block) since the sparse builds share K's pattern.
class CellPredictor {
 public:
  CellPredictor(const Mesh& mesh, const ThesisEditOptions& edit, const MachineRates& rates);
  //! It keeps a reference to the mesh: a temporary would dangle.
  CellPredictor(Mesh&&, const ThesisEditOptions&, const MachineRates&) = delete;
  ~CellPredictor();
  //! \throw Error for an unknown system, build or backend.
  DeformPrediction predict(const DeformCell& cell);

 private:
  const FactorCount& factor(const DeformCell& cell, int block, const std::string& ordering);
  const EnergyOperator& op(const std::string& system);

  const Mesh& mesh_;
  MachineRates rates_;
  Points Vn_;
  Adjacency adj_;
  Unknowns unk_;
  std::map<std::string, std::unique_ptr<EnergyOperator>> ops_;
  std::map<std::string, FactorCount> factors_;
};

}  // namespace db::harness
