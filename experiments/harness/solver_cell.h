#pragma once
//! The solver cell (kind "solve"): one backend and ordering on the LAP or TF normal system of the thesis edit
//! (harness/thesis_edit.h: whole-mesh ROI, 100 handle vertices at one extreme, 100 anchors at the other; soft
//! constraints, so K is #V x #V or 3#V x 3#V), built with the structured build. Used by the solver study; the
//! tracking suite can list such cells as data.
//!
//! Right-hand sides: the deformation's own (the full drag of the handle) and a synthetic b = K x_ref for a
//! seeded random x_ref, whose exact solution is known. Measures: vertices, n, nnz, rhs_cols, build_s, order_s,
//! analyze_s, factorize_s and solve_s (medians over the repetitions, with their spread: factorize_min_s,
//! factorize_max_s, factorize_reps, ...; core/spread.h spread_name), nnz_factor,
//! factor_flops, gflops, matrix_bytes, factor_bytes, baseline_rss_bytes, peak_rss_bytes, iterations (iterative
//! backends), residual (||K x - b|| / ||b||), residual_synthetic, error_exact (||x - x_ref|| / ||x_ref||).
//! build_cpu_s, analyze_cpu_s, factorize_cpu_s, solve_cpu_s: the same phases in CPU time of this process
//! (harness/cpu_timer.h; factorize and solve: the median per repetition, with its spread).
//! String: ordering_used. factor_dir=DIR keeps an out-of-core backend's factor there. With positions=PATH the deformed (normalized) positions go there, for the parent's
//! error_vs_cholmod (harness/positions.h).
//!
//! Orderings: every value the backend accepts, plus "vertex-metis" / "vertex-amd": the deformer's own path, the
//! unknowns renumbered on the vertex graph before assembly and the solver run with the natural ordering (its cost
//! is order_s, counted into analyze_s).
//!
//! Other systems than the thesis edit's (source=...): "edit" takes `mesh` as an edit (a .edit file or BS08 stem,
//! edit/edit_io.h) and `options` as deform options ("key=value;key=value", methods/deform_options.h), and
//! `system` names one of the method's systems (methods/edit_system.h: lap, tf, lri-frames, lri-positions);
//! "matrix" takes `mesh` as a Matrix Market SPD matrix, `rhs` (optional) as its right-hand sides and `block` as
//! its unknowns per vertex
//! (systems/matrix_market.h). Their cells run the registry's backends with the backends' own orderings; without
//! a right-hand side (lri, a matrix alone) the deformation's is the synthetic one. `threads` is recorded (the
//! parent sets the environment, harness/thread_policy.h) beside what the child's libraries report:
//! blas_threads_used, omp_threads_used, own_threads_used.
//!
//! Backend "spqr" is least squares on the naive build's A itself (solvers/least_squares.h: QR, A^T A never
//! formed): its analyze is part of its factorize (analyze_s = 0), its residuals are those of the normal
//! equations its solution satisfies, and error_exact uses b = A x_ref.
#include <string>

#include "solvers/base/types.h"
#include "harness/cell.h"
#include "harness/runner.h"
#include "methods/deform_options.h"
#include "systems/normal_system.h"

namespace db::harness {

//! The least-squares row of the solver study (not a LinearSolver: its input is the rectangular A).
inline const char* const kLeastSquaresBackend = "spqr";

struct SolverCell {
  std::string model, mesh, system = "lap", backend = "cholmod_supernodal", ordering = "default";
  int solve_reps = 10, factor_reps = 5;
  double rep_seconds = 2.0;  //!< stop repeating a phase once it has taken this long in total
  unsigned seed = 1;
  std::string positions;     //!< where to write the deformed positions ("" = nowhere)
  std::string factor_dir;    //!< out of core: SolverOptions::factor_dir ("" = the factor in memory)
  std::string source;        //!< "" (the thesis edit on `mesh`), "edit" or "matrix"
  std::string options;       //!< source=edit: deform options, "key=value;key=value"
  std::string rhs;           //!< source=matrix: the right-hand sides' file ("" = none)
  int block = 1;             //!< source=matrix: unknowns per vertex block (SolverOptions::block_size)
  int threads = 0;           //!< the count the parent set (0: as inherited)

  CellSpec to_spec() const;
  //! \throw UsageError on an unknown key or a malformed number.
  static SolverCell from_spec(const CellSpec& spec);
  std::string key() const;  //!< "hand/tf/cholmod_supernodal/default"
};

//! Family of a backend in the study: the registry's, "least-squares" for spqr.
std::string solver_family(const std::string& backend);
//! Orderings a backend accepts in the study (the registry's; spqr's own).
std::vector<std::string> solver_orderings(const std::string& backend);

//! The cell's system without a solver (for drivers that run their own, e.g. MUMPS under mpirun): the structured
//! build's K (upper triangle), the full drag's right-hand side, and what the rows report.
struct ThesisSystem {
  SpMat K;
  DenseMat rhs;
  int vertices = 0, block = 1;
  double build_s = 0;  //!< the structured build alone (mesh reading and the edit not counted)
};
//! \throw InputError for a mesh that cannot be read or is degenerate.
ThesisSystem build_thesis_system(const std::string& mesh, const std::string& system);

//! The same system's pattern alone, for an analysis that needs no values (MUMPS's estimates of systems too large
//! to build on one machine): K's upper triangle is `pattern` (block columns of the unknowns) expanded to
//! block x block entries (systems/normal_system.h, expand_upper), no entry of K or the right-hand side formed.
struct ThesisPattern {
  InteractionPattern pattern;
  int vertices = 0, block = 1;
  double build_s = 0;  //!< the pattern alone (mesh reading and the edit not counted)
  long long n() const {
    return pattern.colptr.empty() ? 0 : block * (static_cast<long long>(pattern.colptr.size()) - 1);
  }
  //! Entries of K's upper triangle: b^2 per off-diagonal block, b (b + 1) / 2 per diagonal one.
  long long nnz_upper() const;
};
//! \throw InputError as build_thesis_system.
ThesisPattern build_thesis_pattern(const std::string& mesh, const std::string& system);

//! source=edit's options: "key=value;key=value" (deform option keys) set and checked together (resolve_options).
//! \throw UsageError naming the option.
DeformOptions parse_option_items(const std::string& text);
//! The options that shape the system (methods/deform_option_flags.h, system_option_groups) and differ from the
//! defaults, in that form.
std::string option_items_text(const DeformOptions& o);

CellResult measure_solver_cell(const CellSpec& spec);
inline CellKind solver_kind() { return {"solve", measure_solver_cell}; }

}  // namespace db::harness
