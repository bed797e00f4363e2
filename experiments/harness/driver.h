#pragma once
//! Pieces every experiment driver's command line shares (on core/cli.h): the config file, output checks made
//! before any work, and the run's settings written beside its CSVs for the report step.
#include <string>
#include <utility>
#include <vector>

#include "core/cli.h"
#include "core/csv.h"
#include "harness/cell.h"

namespace db::harness {

//! Adds --config FILE: a TOML/INI file of the driver's own options (`frames = 20`, `tier = ["a=b", "c=d"]`;
//! CLI11 reads it), the command line winning over it. Default `default_file` (read when it exists); a key that
//! is no option of the driver is an error, like a misspelled option.
void add_config_option(CLI::App& app, const std::string& default_file);

//! Checks an output directory before any work: it is a writable directory, or missing with a writable nearest
//! existing ancestor (it is created when written to). \throw UsageError naming `option`.
void check_output_dir(const std::string& option, const std::string& dir);

//! Writes `setting,value` rows (with the provenance columns) to `path`, atomically, creating its directory: the
//! settings of the run (budgets, rates, the config file), which the Markdown reports quote.
void write_settings(const std::string& path, const std::vector<std::pair<std::string, std::string>>& settings);

//! Long rows of one cell: `key` columns, then measure, value, unit, status, message for every measure of the
//! schema `defs` keeps (tidy_measures).
void add_measure_rows(CsvTable& csv, const CsvTable::Row& key, const CellResult& r, const std::vector<MeasureDef>& defs);

//! A wide row's spread columns of the timed measure `name` of `r` (spread_name: NAME_min_s, NAME_max_s, NAME_reps),
//! empty where not measured.
void add_spread_columns(CsvTable::Row& row, const CellResult& r, const std::string& name);

//! Exit code of a driver run in which a cell failed (status "error": it crashed, timed out, threw, or its input could
//! not be loaded). The driver still runs every other cell and writes every row (the failed ones with their status);
//! budget refusals (#over, #slow: predicted over budget, never attempted) and skipped cells are no failures, and
//! neither is a solver or method failure the cell measured (its child's exit 3, kSolverFailureExit: a backend that
//! does not converge or finds the system singular, LRI frames that degenerate): that is a result of the study,
//! written in its row with the message.
constexpr int kCellsFailedExit = 5;
//! ChildRun::describe() of a cell whose child ended with a SolverError (exit_code(): 3).
inline const char* const kSolverFailureExit = "exit 3";

//! The failed cells of a driver's run, for its exit: note() every result, return exit_code() at the end.
class FailedCells {
 public:
  explicit FailedCells(std::string driver) : driver_(std::move(driver)) {}
  //! Remembers the cell when `r` failed (once per spec: a result reused for another table is one cell).
  void note(const std::string& spec_text, const CellResult& r);
  std::size_t size() const { return failed_.size(); }
  //! 0 when no cell failed; else lists every failed cell on stderr (its spec, how the child ended, the message)
  //! and returns kCellsFailedExit.
  int exit_code() const;

 private:
  std::string driver_;
  std::vector<std::pair<std::string, std::string>> failed_;  // spec text, why
};

}  // namespace db::harness
