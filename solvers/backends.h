#pragma once
//! Factories of the individual backends; registry.cpp maps names to them. Internal to solvers/.
#include <memory>
#include <string>
#include <vector>

#include "solvers/linear_solver.h"

namespace db::backends {

//! CHOLMOD, supernodal LL^T (`supernodal` true) or simplicial LDL^T.
std::unique_ptr<LinearSolver> make_cholmod(bool supernodal, const SolverOptions& options);

//! Multifrontal supernodal LL^T, symbolic phase on the block graph, subtrees on worker threads.
//! Double: "multifrontal". Mixed ("multifrontal_mixed"): the factor rounded to single precision, each solve
//! refined (double-double residuals, CG corrections preconditioned by it) to SolverOptions::tolerance. Refined
//! ("multifrontal_refined"): the double factor, its solves refined the same way (an accuracy reference).
enum class Precision { Double, Mixed, Refined };
std::unique_ptr<LinearSolver> make_multifrontal(const SolverOptions& options, Precision precision = Precision::Double);

//! Dense on the expanded matrix: kind "llt" (Eigen), "potrf" (LAPACK dpotrf), "ldlt_bk" (LAPACK dsytrf), "lu"
//! (LAPACK dgetrf).
std::unique_ptr<LinearSolver> make_dense(const std::string& kind, const SolverOptions& options);

//! Eigen SimplicialLLT (`ldlt` false) / SimplicialLDLT on the upper triangle.
std::unique_ptr<LinearSolver> make_eigen_simplicial(bool ldlt, const SolverOptions& options);
//! Eigen SparseLU on the full matrix.
std::unique_ptr<LinearSolver> make_eigen_sparse_lu(const SolverOptions& options);

//! UMFPACK LU on the full matrix.
std::unique_ptr<LinearSolver> make_umfpack(const SolverOptions& options);
//! Conjugate gradients, Jacobi (`ichol` false) or incomplete-Cholesky preconditioned.
std::unique_ptr<LinearSolver> make_cg(bool ichol, const SolverOptions& options);

//! MUMPS's multifrontal LDL^T (symmetric positive definite) on this process; MPI initialized on first use. Under a
//! launcher with more than one rank (mpi::launched(), mpi::size() > 1): make_mumps_on_ranks().
std::unique_ptr<LinearSolver> make_mumps(const SolverOptions& options);
//! MUMPS on every rank of MPI_COMM_WORLD behind the LinearSolver contract: every rank calls each phase with the
//! same system and passes MUMPS its own share of the columns; every rank gets the solution. `refined`
//! ("mumps_refined", on any number of ranks, one included): each solve refined as multifrontal_refined's
//! (double-double residuals, CG corrections preconditioned by MUMPS's solve) to SolverOptions::tolerance, the
//! products with A summed over the ranks' shares.
std::unique_ptr<LinearSolver> make_mumps_on_ranks(const SolverOptions& options, bool refined = false);
//! The orderings it accepts (SCOTCH's where Debian's ptscotch build of MUMPS is linked).
std::vector<std::string> mumps_orderings();
//! mumps_orderings() less "metis" (distributed input).
std::vector<std::string> mumps_refined_orderings();

}  // namespace db::backends
