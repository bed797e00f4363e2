#pragma once
//! The numeric work on one supernode of the multifrontal factorization: its front is assembled from the
//! matrix and from its children's update matrices (extend-add), its columns are factored left-looking over
//! column panels with LAPACK/BLAS-3 (dpotrf, dtrsm, dsyrk/dgemm: large calls on dense blocks), and its update
//! matrix (Schur complement) is formed for its parent.
//!
//! The top phase's fronts are shared by a Team (solvers/base/team.h): their products and extend-adds are cut into
//! tiles of rows or columns, each one single-threaded BLAS call per panel, which the team's threads claim. The
//! tiles depend only on the front, never on the team's size, and each writes entries no other tile writes, so the
//! factor's bytes do not depend on which thread ran what.
#include <atomic>
#include <cstdint>
#include <vector>

#include "solvers/base/team.h"
#include "solvers/base/types.h"
#include "solvers/multifrontal/matrix_chunk.h"
#include "solvers/multifrontal/storage.h"
#include "solvers/multifrontal/symbolic.h"

namespace db::multifrontal {

//! Per-thread scratch: row -> front position map, relative indices and the ends of their runs, a front's tiles.
struct Workspace {
  std::vector<int> map, rel, run_end;
  std::vector<int> tiles;
  std::vector<double> diag;  //!< a panel's diagonal block, unpacked for dpotrf
  explicit Workspace(int n) : map(std::size_t(n), -1), diag(std::size_t(FactorBlock::kWidth) * FactorBlock::kWidth) {}
};

//! Which columns of a child's update matrix an extend-add moves: those landing in the parent's own columns
//! (its factor block), those landing in its update matrix, or both.
enum Part { kPivot = 1, kUpdate = 2, kBoth = 3 };

//! The state one numeric factorization shares among its threads: the factor's values (the FactorBlocks of all
//! supernodes, starting as zeros), the update matrices alive, the pivots and the first failed column. The
//! caller runs each supernode after its children, and no two threads on the same supernode.
class FrontFactorization {
 public:
  //! `values`: S.xptr.back() zeroed doubles; `pivots`: S.n entries, L_jj^2 per column once factored;
  //! `pool_bytes`: room for the update matrices in a recycled pool (UpdatePool; the bound of update_peak).
  FrontFactorization(const Symbolic& S, double* values, std::vector<double>& pivots, std::size_t pool_bytes = 0);

  //! Assembles and factors the front of supernode s and forms its update matrix; false (and failed_column()
  //! set) when a pivot is not positive. `M`: a run of supernodes' matrix entries that holds s's. With a `team`
  //! (the top phase) its threads share the work in tiles; the BLAS must then run single-threaded.
  bool factor_supernode(const MatrixChunk& M, int s, Workspace& ws, Team* team = nullptr);
  //! Extend-add of `part` of child c's update matrix into supernode p's factor block and update matrix (with
  //! kUpdate, p's update matrix is allocated zeroed here if it has none yet); frees the child's matrix once
  //! nothing of it is left to move. The caller makes sure no other thread works on p meanwhile.
  void assemble_child(int c, int p, Workspace& ws, Part part = kBoth, Team* team = nullptr);
  //! The update matrices' pool takes no more blocks and hands its free pages back (the top phase: its few large
  //! matrices are mapped each, and the pool's pages would stay resident beside the finished factor).
  void close_pool() { pool_.close(); }
  //! The first column found not positive definite (factor order), or -1.
  std::int64_t failed_column() const { return failed_column_; }

 private:
  FactorBlock block(int s) const { return {values_ + S_.xptr[std::size_t(s)], S_.nrows(s), S_.ncols(s)}; }
  void add_matrix_entries(const MatrixChunk& M, int s, const FactorBlock& L, Workspace& ws) const;
  bool factor_panels(int s, const FactorBlock& L, Workspace& ws, Team* team);
  void form_update(int s, const FactorBlock& L, bool fresh_heap, Workspace& ws, Team* team);

  const Symbolic& S_;
  double* values_;
  std::vector<double>& pivots_;
  UpdatePool pool_;  // before updates_: the blocks go back to it when they die
  std::vector<UpdateBlock> updates_;  //!< update matrix of each supernode until its parent takes it
  std::atomic<std::int64_t> failed_column_{-1};
};

}  // namespace db::multifrontal
