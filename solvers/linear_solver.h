#pragma once
//! One interface for every linear solver backend, in the shape of Eigen's sparse solver concept:
//! analyze(pattern) once per sparsity pattern, factorize(values) once per edit, solve(B) every frame.
//! Systems are symmetric; they are passed as the UPPER triangle in CSC (what CHOLMOD's stype=+1 reads).
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "solvers/base/elimination_tree.h"
#include "solvers/base/types.h"

namespace db {

struct SolverOptions {
  //! Fill-reducing ordering for sparse direct backends: "amd", "metis", "nesdis", "natural", or
  //! "default" (the backend's own choice; CHOLMOD: AMD, plus METIS when AMD's fill is high).
  std::string ordering = "default";
  //! When > 1 the unknowns come in interleaved blocks of this size sharing one pattern (x,y,z of a
  //! vertex); backends may order the compressed block graph and expand it (cheaper analysis).
  int block_size = 1;
  //! Iterative backends: relative residual tolerance and iteration cap. multifrontal_mixed: the relative size
  //! (max-norm) its refinement's last correction of x must fall to, and the cap on the CG iterations of a solve.
  double tolerance = 1e-10;
  int max_iterations = 10000;
  //! Out of core: when not empty, a backend that can (SolverInfo::out_of_core) keeps its factor in an unlinked
  //! scratch file in this directory and holds only the part it is working on in memory. For factors larger
  //! than memory; the solves then read the factor back from the page cache or the disk.
  std::string factor_dir;
  //! Reject a factorization whose smallest pivot over its diagonal entry, d_k / A_kk, is below
  //! singular_pivot_bound(n) as numerically singular: a heuristic for singular positive semidefinite input,
  //! whose pivots end at rounding noise. Callers that know their system is regular turn it off (the
  //! Laplacian deformers, once the constraints are seen to pin the energy's null space): a regular but
  //! ill-conditioned system of millions of unknowns can fall below the bound. Non-positive pivots are always
  //! rejected. The multifrontal, CHOLMOD and dense LL^T backends honour it; the others always test.
  bool pivot_singularity_test = true;
  //! 1: every process passes the whole system. N > 1: each of N ranks (MPI_COMM_WORLD under a launcher) passes
  //! only its own share, and the system is their sum: the matrix's entries (an entry two ranks pass is added) and
  //! the right-hand sides' (each rank passes n rows, zero where it has nothing); every rank gets the solution.
  //! Only `mumps` on exactly N ranks takes it (make_solver refuses the others).
  int rank_shares = 1;
  //! Bytes this process may hold when the factorization peaks; 0: unchecked. A backend that knows its factor's
  //! size once analyze() has run (SolverInfo::checks_memory) measures what the process holds when factorize()
  //! starts and throws BudgetError before allocating if that plus its factor and workspace would pass the
  //! budget. The others ignore it: their callers predict the peak instead (methods/run_prediction.h).
  std::size_t memory_budget = 0;
  //! The elimination tree and column counts of the block graph (blocks of block_size) of the matrix analyze() will
  //! get, in its order, where the caller knows them: the structured builds' dissected vertex orderings find them on
  //! the worker threads. A backend that analyzes the matrix as ordered (ordering "natural") takes them instead of
  //! finding them again on one thread (the multifrontal backends); the others ignore them. They must be that graph's:
  //! the backend checks their shape against the pattern (analyze() throws SolverError where it does not fit), not
  //! every count.
  std::shared_ptr<const EliminationTree> elimination_tree;
};

//! 10 n eps: the smallest d_k / A_kk the pivot test accepts. On singular bi-Laplacians (no constraints) the last
//! pivot is rounding noise of order n eps A_kk, while constrained systems of the same size keep d_k / A_kk
//! orders of magnitude above it.
double singular_pivot_bound(std::size_t n);

struct FactorStats {
  std::size_t n = 0;
  std::size_t nnz_matrix = 0;  //!< stored nonzeros of the input (upper triangle)
  std::size_t nnz_factor = 0;  //!< nonzeros of L (or L+U); 0 for iterative
  double flops = 0;            //!< factorization flops where the backend reports them, else 0
  std::size_t factor_bytes = 0;  //!< bytes held by the factor (values + indices)
  bool factor_on_disk = false;  //!< out of core: the factor's values live in a scratch file, not in memory
  //! Smallest pivot over its diagonal entry, d_k / A_kk (a conditioning indicator: the pivot test rejects
  //! values under singular_pivot_bound(n)); 0 where the backend does not check pivots.
  double min_pivot_ratio = 0;
  //! Bytes the factorization holds at once besides the factor and the input (the multifrontal update matrices,
  //! an upper bound from the schedule); 0 where the backend does not say.
  std::size_t workspace_bytes = 0;
  //! The multifrontal backends' top phase (multifrontal/schedule.h): the flops of the supernodes factored one
  //! after another with the BLAS's threads once the subtrees are done, and that phase's wall time in the last
  //! factorization; 0 with one thread (no top phase) and where the backend has no such phase.
  double top_flops = 0;
  double top_seconds = 0;
  std::string ordering_used;
  int iterations = 0;          //!< iterative backends (and multifrontal_mixed): iterations of the last solve
  double achieved_tolerance = 0;  //!< the same: the last solve's relative residual ||b - A x|| / ||b|| (worst column)
  double last_correction = 0;  //!< multifrontal_mixed: ||d|| / ||x|| (max-norms) of the last solve's last correction
};

class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  virtual std::string name() const = 0;
  //! Symbolic phase from the pattern of A (upper triangle, CSC).
  virtual void analyze(const SpMat& upper) = 0;
  //! Numeric phase. \throw SolverError with the reason (e.g. "not positive definite at column k").
  virtual void factorize(const SpMat& upper) = 0;
  //! factorize(upper) for a caller that has no further use for the matrix: `upper` is left empty, also when
  //! this throws. A backend may hand the matrix's memory back while it factors, which lowers the peak (the
  //! multifrontal one returns each column once the supernodes that read it are done); the default factors, then
  //! clears.
  virtual void factorize_consuming(SpMat& upper) {
    const ClearOnExit clear{upper};
    factorize(upper);
  }
  //! Dense input: `full` is the whole symmetric matrix (both triangles), as the dense build forms it; it is
  //! taken over (left empty). Replaces analyze + factorize. Backends of family "dense" implement it; the others
  //! throw Error (they take sparse input only). \throw SolverError as factorize().
  virtual void factorize_dense(DenseMat& full);
  //! X = A^{-1} B for any number of columns. \throw SolverError on a non-finite result or no convergence.
  virtual void solve(const DenseMat& B, DenseMat& X) = 0;
  virtual FactorStats stats() const = 0;

  //! Per-frame fast path for right-hand sides that differ from a fixed B0 only in a few rows (interactive
  //! editing: only rows coupled to the handle change). After set_base_rhs(B0, rows), solve_changed(B)
  //! returns what solve(B) returns. A backend may precompute the forward substitution of B0 and redo only
  //! the part reached from `rows`; the default simply solves. A B that differs from B0 outside `rows` is
  //! still solved correctly (in full). Call set_base_rhs again after each factorize().
  virtual void set_base_rhs(const DenseMat& B0, const std::vector<int>& rows) {
    (void)B0;
    (void)rows;
  }
  virtual void solve_changed(const DenseMat& B, DenseMat& X) { solve(B, X); }

 protected:
  //! Empties the matrix when it goes out of scope (factorize_consuming's promise, exceptions included).
  struct ClearOnExit {
    SpMat& m;
    ~ClearOnExit() { m = SpMat(); }
  };
};

//! Backend by name; see solver_names(). \throw Error for an unknown name (the message lists the valid ones).
std::unique_ptr<LinearSolver> make_solver(const std::string& name, const SolverOptions& options = {});
//! Every registered backend name.
std::vector<std::string> solver_names();

//! What callers (tables, the conformance test) need to know about a registered backend.
struct SolverInfo {
  std::string name;
  std::string family;  //!< "sparse-cholesky", "sparse-lu", "dense", "iterative"
  bool requires_spd = true;  //!< factorize() throws SolverError on indefinite / singular input
  std::vector<std::string> orderings;  //!< values of SolverOptions::ordering it accepts
  bool out_of_core = false;  //!< accepts SolverOptions::factor_dir
  //! With ordering "natural" it eliminates in exactly the given order. MUMPS takes a given order as the start of
  //! its analysis and eliminates in an equivalent one (the same fill; pivots met in another order).
  bool keeps_natural_order = true;
  //! factorize() honours SolverOptions::memory_budget with its exact sizes.
  bool checks_memory = false;
};
//! \throw Error for an unknown name.
SolverInfo solver_info(const std::string& name);

}  // namespace db
