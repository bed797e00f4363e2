#pragma once
//! Helpers shared by the solver backends (not part of the public solver contract).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "solvers/base/types.h"
#include "solvers/linear_solver.h"

namespace db::solver_util {

//! Largest system a dense backend accepts: 16000^2 doubles = 2 GB; beyond that refuse instead of allocating.
constexpr Index kMaxDenseUnknowns = 16000;

//! \throw Error when options.ordering is not one the registry lists for backend `who` (solver_info), or
//! options.block_size < 1.
void check_options(const SolverOptions& options, const std::string& who);
//! \throw SolverError unless `upper` is square.
void check_square(const SpMat& upper, const std::string& who);
//! \throw SolverError naming the first NaN/Inf entry of the matrix values.
void check_finite_values(const SpMat& upper, const std::string& who);
//! \throw SolverError when B's row count does not match n.
void check_rhs(const DenseMat& B, Index n, const std::string& who);
//! \throw SolverError when the solution holds a NaN/Inf (never hand back NaN silently).
void check_finite_result(const DenseMat& X, const std::string& who);
//! \throw BudgetError when an n x n dense matrix would exceed kMaxDenseUnknowns.
void check_dense_budget(Index n, const std::string& who);

//! For its lifetime, every OpenMP parallel region of the libraries in this process runs on one thread
//! (omp_set_max_active_levels(0), found with dlsym: the project itself does not link OpenMP; restored afterwards).
//! CHOLMOD's supernodal factorization opens OpenMP regions with a thread count fixed when SuiteSparse was built
//! (OMP_NUM_THREADS does not lower it) between the BLAS calls that do its flops; the idle OpenMP threads then spin
//! on the cores the BLAS threads need (results/records/2026-11-26-cholmod-threads). Not thread-safe: the setting
//! is the process's.
class OpenMpSerial {
 public:
  OpenMpSerial();
  ~OpenMpSerial();
  OpenMpSerial(const OpenMpSerial&) = delete;
  OpenMpSerial& operator=(const OpenMpSerial&) = delete;

 private:
  void (*set_)(int) = nullptr;
  int saved_ = 0;
};

//! `m` itself when compressed, else a compressed copy in `storage` (raw CSC views need packed arrays).
const SpMat& compressed(const SpMat& m, SpMat& storage);

//! Full symmetric matrix from the upper triangle (entries below the diagonal are ignored).
//! Take the result with `full_from_upper(u).swap(dst)`: assigning a returned SparseMatrix copies it (Eigen 3.4
//! has no move assignment for sparse matrices).
SpMat full_from_upper(const SpMat& upper);
//! Dense full symmetric matrix from the upper triangle (call check_dense_budget first).
DenseMat dense_from_upper(const SpMat& upper);

//! Remembers the pattern given to analyze() so factorize() can refuse a different one
//! (a factor from a stale symbolic analysis would be silently wrong).
class PatternGuard {
 public:
  void remember(const SpMat& upper);
  bool empty() const { return !set_; }
  //! \throw SolverError when `upper` has another size or pattern than the remembered one.
  void check(const SpMat& upper, const std::string& who) const;

 private:
  // Size, nonzeros and a 64-bit hash of the index arrays, not a copy of them (as large as the matrix's indices).
  std::size_t n_ = 0, nnz_ = 0;
  std::uint64_t hash_ = 0;
  bool set_ = false;
};

//! The shared prologue of factorize(): compresses `in` (into `storage` when needed), runs solver.analyze() when
//! no pattern was analyzed yet and otherwise checks it is the analyzed one, and rejects non-finite values.
//! Returns the compressed matrix (`in` or `storage`).
const SpMat& prepare_factorize(LinearSolver& solver, const PatternGuard& guard, const SpMat& in, SpMat& storage);

//! Cholesky-style flop count from column counts of L (diagonal included): sum_j c_j^2,
//! the same estimate CHOLMOD reports in Common->fl.
double cholesky_flops(const int* col_ptr, Index n);

//! Pivot test after a Cholesky-type factorization. `pivots[k]` is the k-th pivot in factor order
//! (L_kk^2 or D_kk), `perm[k]` the original index of that pivot (null: identity).
//! \throw SolverError "not positive definite" on a pivot <= 0, and, with `singular_test`, "numerically
//! singular" when some pivot looks like rounding noise relative to its diagonal entry:
//! d_k / A_kk < singular_pivot_bound(n) (see SolverOptions::pivot_singularity_test).
//! It is a heuristic: a severely ill-conditioned but regular system can be flagged (the TF system at millions
//! of unknowns is), and a singular one whose noise pivot lands above the bound passes (its solution is then
//! finite but meaningless).
//! \return the smallest d_k / A_kk (FactorStats::min_pivot_ratio).
double check_pivots(const std::vector<double>& pivots, const int* perm, const SpMat& upper, const std::string& who,
                    bool singular_test = true);
//! The same against the matrix's diagonal taken beforehand (diagonal_of), for a matrix released meanwhile.
double check_pivots(const std::vector<double>& pivots, const int* perm, const DenseVec& diag, const std::string& who,
                    bool singular_test = true);
DenseVec diagonal_of(const SpMat& upper);

//! Compressed block graph of a pattern: node I stands for unknowns b*I .. b*I+b-1 (x,y,z of a vertex).
//! Full symmetric adjacency without the diagonal, sorted, no duplicates.
struct BlockGraph {
  int nb = 0;
  std::vector<int> Ap, Ai;
};
//! Block graph of the upper triangle `upper` (columns a multiple of b).
BlockGraph block_graph(const SpMat& upper, int b);

}  // namespace db::solver_util
