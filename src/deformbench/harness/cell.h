#pragma once
//! A cell: one (model, system, build, backend) measurement of the thesis Table 2-1 grid, run in a fresh child
//! process. The parent re-executes its own driver with `--cell ...` arguments (CellSpec::to_args); the child
//! measures (measure_cell) and prints exactly one line "DBCELL key=value ..." on stdout (encode_result);
//! the parent decodes it and adds what only it can see (wait4's ru_maxrss, wall time, the prediction).
#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "core/args.h"
#include "harness/thesis_edit.h"

namespace db::harness {

struct CellSpec {
  std::string model;      //!< tier label for result rows ("hand", "armadillo_loop2")
  std::string mesh_path;  //!< mesh file the child reads
  std::string system = "tf";            //!< "lap" | "tf"
  std::string build = "structured";     //!< "dense" | "naive" | "structured"
  std::string backend = "multifrontal";  //!< solver registry name (dense build: Eigen's LLT, see backend_label)
  std::string ordering = "default";
  //! Out of core: the factor goes to a scratch file in this directory (SolverOptions::factor_dir); "" = memory.
  std::string factor_dir;
  int frames = 20;
  ThesisEditOptions edit;
  std::size_t memory_budget_bytes = 0;  //!< handed to DeformOptions::memory_budget (the systems layer's own check)
  std::size_t address_space_limit = 0;  //!< child's RLIMIT_AS, bytes; 0 = none (a safety net against swapping the box)

  //! "--cell --model hand --mesh ... " (argv after the executable).
  std::vector<std::string> to_args() const;
  //! \throw Error on a missing or malformed option.
  static CellSpec from_args(const Args& a);
  //! The backend that actually factors: the dense build always uses Eigen's dense LLT.
  std::string backend_label() const { return build == "dense" ? "eigen_llt" : backend; }
  //! "hand/tf/structured/multifrontal"
  std::string key() const;
  //! "disk" when the factor is kept out of core, else "memory".
  std::string factor_storage() const { return factor_dir.empty() ? "memory" : "disk"; }
};

//! What a bounded, budget-checked cell was predicted to need before it was allowed to run.
struct Prediction {
  double build_bytes = 0;   //!< predict_build_bytes (dense: includes the LLT's copy of K)
  double factor_bytes = 0;  //!< dense: n^2 * 8; sparse: from a symbolic analysis of the vertex graph
  double workspace_bytes = 0;  //!< the factorization's working storage besides the factor (update matrices)
  double total_bytes = 0;   //!< what the memory budget is checked against
  double factor_nnz = 0, factor_flops = 0, build_flops = 0;
  double seconds = 0;       //!< what the time budget is checked against (build + analyze + factor + frames)
  std::string basis;        //!< how the factor was predicted, for the report
};

//! One cell's measurements. Every number is a double (byte counts stay exact below 2^53); NaN = not measured.
struct CellResult {
  std::string status = "ok";  //!< ok | #over | #slow | error
  std::string message;        //!< why, for anything but ok
  std::string ordering;       //!< fill-reducing ordering the backend used
  // Measured by the child.
  double vertices, n, nnz, nnz_factor, factor_flops, min_pivot_ratio;
  double build_s, analyze_s, factorize_s, init_s;
  double frames, frame_s, rhs_s, solve_s, write_s, fps;  // medians over frames; fps = 1 / frame_s
  double matrix_bytes, factor_bytes, held_total_bytes;
  double peak_rss_bytes;      //!< child's VmHWM at the end (its own address space only)
  double baseline_rss_bytes;  //!< child's VmRSS after reading the mesh, before the deformer
  double mean_displacement;   //!< mean |v' - v| of the last frame / bbox diagonal (cross-build sanity check)
  std::vector<std::pair<std::string, double>> held_bytes;  //!< matrices held by the build, by name
  // Added by the parent.
  double ru_maxrss_bytes, parent_rss_bytes, wall_s;
  double runs;       //!< fresh children this result is the median of (median_of)
  std::string exit;  //!< how the child ended ("exit 0", "signal 9 (Killed)", ...)
  Prediction predicted;

  CellResult();
  bool ok() const { return status == "ok"; }
};

//! A named value for tidy (long) rows: measure, value, unit.
struct Measure {
  std::string name;
  double value;
  std::string unit;
};
//! Every measure of a cell in a fixed order (held bytes as "held_bytes:<name>"). Cells that did not run keep
//! the core measures (value NaN) so every (model, system, build) has the same rows.
std::vector<Measure> measures(const CellResult& r);

//! "DBCELL status=ok n=1197 ..." (values percent-encoded: no spaces, '=' or newlines inside).
std::string encode_result(const CellResult& r);
//! Parses the last "DBCELL " line of a child's stdout. \throw Error when there is none or it is malformed.
CellResult decode_result(const std::string& child_stdout);

//! Runs the cell in this process: reads the mesh, makes the thesis edit, builds the deformer (soft constraints)
//! and drags the handle over spec.frames frames. \throw whatever the layers below throw.
CellResult measure_cell(const CellSpec& spec);

//! Child entry point for argv = {exe, "--cell", ...}: measures, prints the DBCELL line (also for a failure:
//! BudgetError -> #over, anything else -> error) and returns the exit code (0, or exit_code(e)).
int cell_main(int argc, char** argv);

//! Runs `exe` + spec.to_args() in a fresh child process and returns its measurements, plus ru_maxrss, wall time
//! and the parent's own RSS at fork time. A child that crashes, is killed or prints no result line gives
//! status "error" with the reason and the tail of its stderr; never throws for a failing child.
CellResult run_cell_in_child(const std::string& exe, const CellSpec& spec, double timeout_s);

//! Field-by-field median of repeated runs of one cell (all ok), so one disturbed run on a shared machine does
//! not make the table; strings and held bytes come from the first run, `runs` is the count.
//! \throw Error for an empty list.
CellResult median_of(const std::vector<CellResult>& runs);

//! The parent's decision: `#over` when the prediction exceeds the memory budget, `#slow` when it exceeds the
//! time budget (neither calls `runner`); otherwise runner(spec). The prediction is attached to the result.
//! Budgets <= 0 are unlimited.
CellResult run_budgeted(const CellSpec& spec, const Prediction& p, double memory_budget_bytes, double time_budget_s,
                        const std::function<CellResult(const CellSpec&)>& runner);

}  // namespace db::harness
