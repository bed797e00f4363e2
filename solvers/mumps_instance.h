#pragma once
//! One MUMPS instance (double real, SYM=1: symmetric positive definite, LDL^T without pivoting) over an MPI
//! communicator, as both MUMPS backends use it (the `mumps` LinearSolver on one process, DistributedMumps on all
//! ranks): the settings, the job calls, failures as SolverError with MUMPS's code explained, and the statistics
//! MUMPS reports. Internal to solvers/.
//!
//! Settings beyond MUMPS's defaults, and why:
//! - printing off (ICNTL(1..4)); DEFORMBENCH_MUMPS_VERBOSE=1 turns MUMPS's own report on (stdout).
//! - the diagonal scaling 1 / sqrt(A_kk) (diagonal_scaling()): the scaled matrix has a unit diagonal, so its
//!   smallest |pivot| is the smallest d_k / A_kk, which MUMPS records (DKEEP(19), see local_min_pivot()); the
//!   solution is unchanged. Centralized input: given to MUMPS (ICNTL(8)=-1, COLSCA = ROWSCA, set_diagonal()).
//!   Distributed input: MUMPS 5.5 applies neither its own diagonal scaling (ICNTL(8)=1) nor a given one (it
//!   frees the caller's arrays at the end), so the caller scales its entries and the right-hand sides itself
//!   (ICNTL(8)=0).
//! - ordering (ICNTL(7)) from SolverOptions::ordering; "metis" and "natural" are given to MUMPS (ICNTL(7)=1,
//!   PERM_IN): Debian's MUMPS links no METIS, so "metis" is this project's METIS ordering (solvers/ordering) of the
//!   block graph; "ptscotch" is MUMPS's parallel analysis (ICNTL(28)=2, ICNTL(29)=1).
//! - block_size b > 1 with an ordering MUMPS computes: ICNTL(15) = -b, MUMPS compresses the graph to b x b blocks
//!   before ordering it (as the other backends order the block graph).
//! - out of core (ICNTL(22)=1) with OOC_TMPDIR = SolverOptions::factor_dir: MUMPS writes the factor to files
//!   named deformbench-mumps* there and deletes them when the instance ends (JOB=-2) or refactors; a process that
//!   is killed leaves them behind.
//! - a factorization that runs out of MUMPS's estimated workspace (INFOG(1) = -8, -9) is retried with twice
//!   the relaxation (ICNTL(14)), up to three times.
#include <cstddef>
#include <string>
#include <vector>

#include <dmumps_c.h>
#include <mpi.h>

#include "solvers/linear_solver.h"
#include "solvers/mumps_report.h"

#include "solvers/base/cleanup.h"

namespace db::mumps {

//! 1 / sqrt(d_k) for each diagonal entry, 1 for a non-positive one (its pivot fails anyway).
std::vector<double> diagonal_scaling(const std::vector<double>& diagonal);
//! `m` without its entries below the diagonal: `m` itself when it has none, else a copy in `storage`. The contract
//! passes the upper triangle; MUMPS would add a mirrored entry to its twin, so anything below is dropped, as the
//! other backends ignore it.
const SpMat& upper_triangle(const SpMat& m, SpMat& storage);
//! MUMPS's meaning of an error code INFOG(1) < 0, with INFOG(2) where it says more.
std::string error_text(int infog1, int infog2);
//! Name of an ordering MUMPS reports in INFOG(7) ("amd", "amf", "scotch", "pord", "metis", "qamd", "given").
std::string ordering_name(int code);
//! The orderings SolverOptions::ordering may name for the MUMPS backends (with SCOTCH where linked).
std::vector<std::string> orderings();

class Instance {
 public:
  //! JOB=-1 on `comm` (every process of it calls this). `distributed_input`: every process passes its own
  //! entries (IRN_loc, JCN_loc, A_loc; ICNTL(18)=3), else the host passes them all (IRN, JCN, A).
  //! \throw Error for options MUMPS cannot honour (an out-of-core directory that does not exist or is not
  //! writable, or longer than MUMPS's 255 characters).
  Instance(MPI_Comm comm, const SolverOptions& options, const std::string& who, bool distributed_input = false);
  ~Instance();
  Instance(const Instance&) = delete;
  Instance& operator=(const Instance&) = delete;

  DMUMPS_STRUC_C& id() { return id_; }
  const std::string& who() const { return who_; }
  //! Analysis (JOB=1) of the entries the caller has set in id() (centralized or distributed): the ordering,
  //! the block compression. `perm_in` (host only; 1-based positions, PERM_IN) when the ordering is given.
  void analyze(std::vector<int>* perm_in);
  //! Centralized input: the scaling for the next factorization (see above) from the matrix's diagonal (on the
  //! host), kept here.
  void set_diagonal(const std::vector<double>& diagonal);
  //! Factorization (JOB=2) of the values the caller has set; retries on too little workspace. Then the pivot
  //! checks: \throw SolverError when a pivot is negative (not positive definite), or, with
  //! `singular_test`, when the smallest d_k / A_kk is under singular_pivot_bound(n).
  void factorize(bool singular_test);
  //! Solve (JOB=3) with the dense right-hand sides the caller has set on the host.
  void solve();

  //! Smallest |pivot| of the diagonally scaled matrix on this process: MUMPS's internal DKEEP(19), which it
  //! updates at every pivot (DMUMPS_UPDATE_MINMAX_PIVOT in dfac_front_aux.F, MUMPS 5.4/5.5) but does not
  //! document; the conformance test checks it against a dense Cholesky.
  double local_min_pivot() const;
  const Report& report() const { return report_; }
  //! The factorization's part of FactorStats from report(): nnz_factor, flops, factor_bytes (INFOG(9), (10)),
  //! workspace_bytes (INFOG(22) less the factor held in memory), factor_on_disk, min_pivot_ratio, ordering_used.
  void fill_stats(FactorStats& st) const;
  bool factored() const { return factored_; }
  bool given_ordering() const { return given_; }
  //! The ordering for FactorStats::ordering_used: MUMPS's name, "-block<b>" when the graph was compressed;
  //! "metis-block<b>" / "natural" for the given ones.
  std::string ordering_used() const;

 private:
  void call(int job, const char* phase);
  void read_analysis_report();
  void read_factor_report();

  DMUMPS_STRUC_C id_{};
  MPI_Comm comm_;
  SolverOptions options_;
  std::string who_;
  Report report_;
  std::vector<double> scaling_;
  bool given_ = false, compressed_ = false, factored_ = false, alive_ = false, distributed_ = false;
  //! Out of core: MUMPS's files of this process (OOC_PREFIX "deformbench-mumps.PID", one process per rank), removed
  //! on an ending signal (base/cleanup.h); JOB=-2 removes them otherwise.
  cleanup::ScratchPath ooc_files_;
};

}  // namespace db::mumps
