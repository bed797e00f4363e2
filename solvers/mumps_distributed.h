#pragma once
//! MUMPS on every rank of MPI_COMM_WORLD (`mpirun -np N`), with distributed assembled input (ICNTL(18)=3): each
//! rank passes the entries of the upper triangle it built itself, and no rank ever holds the whole matrix. The
//! analysis, the factorization and the solves are collective (every rank calls them, in the same order);
//! right-hand sides and solutions live on rank 0. With one rank it is the `mumps` backend with distributed input.
//! The instance settings (scaling, orderings, out of core, errors) are those of mumps_instance.h; the diagonal
//! scaling is applied here (every rank holds the n scale factors).
#include <memory>
#include <vector>

#include "solvers/base/types.h"
#include "solvers/linear_solver.h"
#include "solvers/mumps_report.h"

namespace db {

namespace mumps {
class Instance;
}

class DistributedMumps {
 public:
  //! Collective. options.ordering: one MUMPS computes (its "default", "amd", ..., "ptscotch") or "natural"
  //! (the caller numbered the unknowns in a fill-reducing order); "metis" would need the whole graph on one
  //! rank and is refused (Error).
  explicit DistributedMumps(const SolverOptions& options);
  ~DistributedMumps();
  DistributedMumps(const DistributedMumps&) = delete;
  DistributedMumps& operator=(const DistributedMumps&) = delete;

  //! Collective: the analysis of this rank's entries (0-based global indices, row <= col, any split between
  //! ranks; an entry two ranks both pass is summed) of an n x n matrix. The arrays are taken over (MUMPS reads
  //! them again at the factorization). \throw SolverError naming MUMPS's error, Error for an entry out of range
  //! or below the diagonal.
  void analyze(Index n, std::vector<int> rows, std::vector<int> cols);
  //! Collective: the analysis of a pattern that rank 0 passes whole (MUMPS's centralized assembled input,
  //! ICNTL(18)=0; the other ranks pass empty arrays and need build nothing): MUMPS's estimates for this many
  //! ranks (report()) of a system too large to build on every rank. Analysis only: factorize() after it throws.
  //! \throw as analyze().
  void analyze_centralized(Index n, std::vector<int> rows, std::vector<int> cols);
  //! Collective: the factorization of this rank's values, in the order of its analyzed entries (taken over).
  //! \throw SolverError: a count that does not match, a non-finite value, MUMPS's errors, pivots as the `mumps`
  //! backend (not positive definite; numerically singular with SolverOptions::pivot_singularity_test).
  void factorize(std::vector<double> values);
  //! Collective: on rank 0, B (n x k) in and X out, in place; the other ranks pass an empty matrix.
  void solve(DenseMat& BX);

  //! MUMPS's figures (global; the per-rank vectors on rank 0 only).
  const mumps::Report& report() const;
  //! As LinearSolver::stats(): n, nnz_matrix (entries over all ranks), nnz_factor, flops, factor_bytes,
  //! factor_on_disk, min_pivot_ratio, ordering_used.
  FactorStats stats() const { return stats_; }

 private:
  //! Checks this rank's entries on every rank (all throw, or none) and keeps them 1-based in irn_, jcn_.
  void take_entries(Index n, std::vector<int> rows, std::vector<int> cols);
  //! JOB=1 on the entries set in the instance; the statistics of the analysis.
  void run_analysis(Index n);
  //! The matrix's diagonal on rank 0 (empty elsewhere), for the scaling.
  std::vector<double> diagonal_on_root() const;

  std::unique_ptr<mumps::Instance> mumps_;
  SolverOptions options_;
  std::vector<int> irn_, jcn_;
  std::vector<double> values_;
  std::vector<double> scaling_;  //!< 1 / sqrt(A_kk), on every rank (values_ are scaled by it)
  bool centralized_ = false;     //!< analyze_centralized(): no factorization
  FactorStats stats_;
};

}  // namespace db
