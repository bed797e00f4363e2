#include "harness/driver.h"

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <iostream>

#include <fmt/format.h>

#include "core/csv.h"
#include "solvers/base/error.h"
#include "harness/toml_config.h"

namespace db::harness {

namespace fs = std::filesystem;

void add_config_option(CLI::App& app, const std::string& default_file) {
  const CLI::Option* config =
      app.set_config("--config", default_file,
                     fmt::format("options file (strict TOML: `option = value`, lists as [\"a\", \"b\"]); the command "
                                 "line wins over it (default {}, when it exists)",
                                 default_file));
  app.config_formatter(strict_toml_config(app, config));
  app.allow_config_extras(CLI::config_extras_mode::error);
}

void check_output_dir(const std::string& option, const std::string& dir) {
  if (dir.empty()) throw UsageError(fmt::format("{}: empty path", option));
  std::error_code ec;
  fs::path p = fs::absolute(dir, ec);
  if (fs::exists(p, ec) && !fs::is_directory(p, ec))
    throw UsageError(fmt::format("{} {}: not a directory", option, dir));
  while (!fs::exists(p, ec) && p.has_parent_path() && p != p.parent_path()) p = p.parent_path();
  if (!fs::is_directory(p, ec))
    throw UsageError(fmt::format("{} {}: '{}' is not a directory", option, dir, p.string()));
  if (::access(p.c_str(), W_OK | X_OK) != 0)
    throw UsageError(fmt::format("{} {}: '{}' is not writable", option, dir, p.string()));
}

void write_settings(const std::string& path, const std::vector<std::pair<std::string, std::string>>& settings) {
  CsvTable csv;
  for (const auto& [k, v] : settings) csv.add({{"setting", k}, {"value", v}});
  if (fs::path(path).has_parent_path()) fs::create_directories(fs::path(path).parent_path());
  csv.write(path);
}

void add_measure_rows(CsvTable& csv, const CsvTable::Row& key, const CellResult& r, const std::vector<MeasureDef>& defs) {
  for (const Measure& m : tidy_measures(r, defs)) {
    CsvTable::Row row = key;
    row.insert(row.end(), {{"measure", m.name},
                           {"value", std::isnan(m.value) ? "" : num(m.value)},
                           {"unit", m.unit},
                           {"status", r.status},
                           {"message", r.message}});
    csv.add(std::move(row));
  }
}

void add_spread_columns(CsvTable::Row& row, const CellResult& r, const std::string& name) {
  for (const char* stat : {"min", "max", "reps"}) {
    const std::string col = spread_name(name, stat);
    const double v = r.get(col);
    row.emplace_back(col, std::isnan(v) ? "" : num(v));
  }
}

void FailedCells::note(const std::string& spec_text, const CellResult& r) {
  if (r.status != "error" || r.exit == kSolverFailureExit) return;
  for (const auto& f : failed_)
    if (f.first == spec_text) return;
  failed_.emplace_back(spec_text, r.exit.empty() ? r.message : fmt::format("{} ({})", r.message, r.exit));
}

int FailedCells::exit_code() const {
  if (failed_.empty()) return 0;
  std::cerr << fmt::format("[{}] {} cell(s) failed (their rows say status error; exit {}):\n", driver_, failed_.size(),
                           kCellsFailedExit);
  for (const auto& [spec, why] : failed_)
    std::cerr << fmt::format("[{0}] FAILED {1}\n[{0}]   {2}\n", driver_, spec, why);
  return kCellsFailedExit;
}

}  // namespace db::harness
