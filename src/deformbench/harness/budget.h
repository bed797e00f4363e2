#pragma once
//! Predicting a cell's memory and time before it is allowed to run (thesis Table 2-1 marks the cells that did
//! not fit its 1 GB machine "#over"; here a cell over budget is never attempted and keeps its prediction).
//!
//! Memory: predict_build_bytes (systems/normal_system.h, from the adjacency alone) + the factor: dense n^2 * 8,
//! sparse from a symbolic analysis of the vertex-level pattern (K's 2-ring graph), expanded to 3x3 blocks for TF.
//! Time: flop counts over rates measured once per run (a dense GEMM, a sparse A^T A product).
#include <map>
#include <memory>
#include <string>

#include "harness/cell.h"
#include "mesh/mesh.h"
#include "methods/normalization.h"
#include "systems/normal_system.h"

namespace db::harness {

//! Machine rates in flop/s, measured once per driver run (a few tenths of a second).
struct MachineRates {
  double dense = 1e9;   //!< Eigen dense GEMM, one thread: the dense build's SYRK and LLT run on this kernel
  double sparse = 1e8;  //!< Eigen sparse A^T A product: what the sparse builds run at (indexing-bound)
  double stream = 1e9;  //!< dense matrix-vector product out of cache: what triangular solves run at (memory-bound)
  static MachineRates measure();
  //! The system BLAS's dgemm on 1024 x 1024 matrices with its own threads (best of three, ~0.2 s): the ceiling
  //! of the sparse factorizations' dense kernels at the moment it runs. On a shared machine it moves by 2x
  //! within a day, so drivers take it next to each cell to tell a slow machine from a slow code.
  static double blas_gemm();
  //! Bytes per second read from memory by worker_threads() threads summing a 128 MB array (best of three): the
  //! rate the triangular solves stream the factor at, at best.
  static double read_bandwidth();
};

//! Predicts every cell of one mesh under the thesis edit. Holds the mesh's adjacency and operators, and caches
//! the vertex-graph factor analysis per (backend, ordering) since the sparse builds share K's pattern.
class CellPredictor {
 public:
  CellPredictor(const Mesh& mesh, const ThesisEditOptions& edit, const MachineRates& rates);
  ~CellPredictor();
  //! \throw Error for an unknown system, build or backend.
  Prediction predict(const CellSpec& spec);

 private:
  struct VertexFactor {
    std::string backend;  // the backend whose analysis counted it
    double nnz = 0, flops = 0;
    double workspace_bytes = 0;  // the backend's working storage besides the factor (FactorStats)
    std::string basis;
  };
  VertexFactor vertex_factor(const std::string& backend, const std::string& ordering);
  const EnergyOperator& op(const std::string& system);

  const Mesh& mesh_;
  MachineRates rates_;
  Points Vn_;
  Adjacency adj_;
  Unknowns unk_;
  std::map<std::string, std::unique_ptr<EnergyOperator>> ops_;
  std::map<std::string, VertexFactor> factors_;
  double vertex_nnz_upper_ = 0;  // nonzeros of the vertex graph's upper triangle (set by vertex_factor)
};

}  // namespace db::harness
