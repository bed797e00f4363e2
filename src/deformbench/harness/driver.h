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

}  // namespace db::harness
