#pragma once
//! Running cells (harness/cell.h) in fresh child processes, so that cells never share a heap, a page cache of
//! freed blocks or a high-water mark.
//!
//! Parent: run_cell() re-executes the driver as `EXE --cell [--address-space-limit=BYTES] key=value ...`, reads
//! the child's DBCELL line and adds what only the parent sees: wait4's ru_maxrss, wall time, how the child ended
//! (exit status, signal, timeout), the memory and time budgets checked against a prediction before the cell is
//! allowed to run, the median over repeated fresh children, the load average and the machine's speed measured
//! just before and after the cell (MachineRates).
//!
//! Child: a driver's main() starts with `if (is_cell_invocation(argc, argv)) return cell_main(argc, argv, kinds);`
//! where `kinds` maps a spec's "kind" to its measure function.
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "harness/cell.h"

namespace db::harness {

//! A measure function: parses the spec (CellSpec::check_keys first) and measures, in the child. Throws as the
//! layers below throw; cell_main turns that into the result's status.
using MeasureFn = std::function<CellResult(const CellSpec&)>;
struct CellKind {
  std::string name;
  MeasureFn measure;
};

//! What a cell is predicted to need before it is allowed to run.
struct Prediction {
  double bytes = 0;    //!< checked against RunOptions::memory_budget_bytes
  double seconds = 0;  //!< checked against RunOptions::time_budget_s; also decides the repeats
  std::vector<Measure> measures;  //!< added to the result whether or not the cell runs ("predicted_bytes", ...)
  std::string basis;   //!< how it was predicted, for the raw cell records
};

struct RunOptions {
  double timeout_s = 0;                 //!< wall-clock limit per child (SIGKILL); 0 = none
  std::size_t address_space_bytes = 0;  //!< the child's RLIMIT_AS; 0 = none (a safety net against swapping the box)
  int repeats = 1;                      //!< fresh children per cell; the result is the median of each measure
  double repeat_max_s = 0;              //!< a cell predicted above this many seconds runs once; 0 = no limit
  bool machine_rates = false;           //!< measure the BLAS dgemm and memory read rates around the cell
  double memory_budget_bytes = 0;       //!< with a prediction: over it the cell is "#over", never attempted
  double time_budget_s = 0;             //!< with a prediction: over it the cell is "#slow", never attempted
};

//! Runs one cell: the budget check (with a prediction), then `repeats` fresh children of `exe` (stopping at the
//! first that fails, whose result is returned as it happened), their median. Measures added by the parent:
//! load_avg_1m, ru_maxrss_bytes, parent_rss_bytes, cell_wall_s, cell_cpu_s (the child's user + system time),
//! runs; with machine_rates blas_dgemm_before|after (GFlop/s) and memory_read_before|after (GB/s), "after" only
//! when the cell succeeded; the prediction's measures. A child that crashes, is killed, times out or prints no
//! result line gives status "error" with the reason and the tail of its stderr. Never throws for a failing child.
CellResult run_cell(const std::string& exe, const CellSpec& spec, const RunOptions& options,
                    const Prediction* prediction = nullptr);

//! argv[1] == "--cell".
bool is_cell_invocation(int argc, char** argv);
//! Child entry point for argv = {exe, "--cell", [--address-space-limit=BYTES], key=value...}: runs the measure
//! function of the spec's kind, prints the DBCELL line (also for a failure: BudgetError -> #over, anything else
//! -> error, with peak_rss_bytes) and returns the exit code (0, or exit_code(e)).
int cell_main(int argc, char** argv, const std::vector<CellKind>& kinds);

//! A kind that Loop-subdivides a mesh (keys in, levels, out): drivers generate missing tiers in a child too, so
//! the parent stays small and its forked image does not inflate the cells' ru_maxrss.
CellKind loop_subdivide_kind();

}  // namespace db::harness
