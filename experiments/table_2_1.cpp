// Thesis Table 2-1: dense, naive sparse and structured sparse builds of the LAP and TF systems on the tiers of a
// config (data/experiments/table_2_1.toml: memory, init time, frame rate), plus a scaling series of the structured
// build with fitted cost exponents. Every cell (harness/deform_cell.h) runs in fresh child processes under a
// memory and a time budget checked against a prediction first; cells over budget are recorded as #over / #slow,
// never attempted. A sparse cell over the memory budget with its factor in memory runs out of core when that fits.
//
// Writes RESULTS/table_2_1.csv (long: one row per model x system x build x measure), table_2_1_thesis.csv,
// scaling.csv, scaling_fits.csv and table_2_1_settings.csv; per-cell raw child lines go to
// RESULTS/cells/table_2_1/. results/table_2_1.md is the report step's (python/dbtools/). Options: --help.
// Exits with kCellsFailedExit (harness/driver.h) when a cell failed, after writing every row.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>

#include <fmt/format.h>

#include "solvers/base/atomic_file.h"
#include "core/cli.h"
#include "core/csv.h"
#include "solvers/base/error.h"
#include "core/provenance.h"
#include "solvers/base/resources.h"
#include "harness/budget.h"
#include "harness/csv_reader.h"
#include "harness/deform_cell.h"
#include "harness/driver.h"
#include "harness/mesh_source.h"
#include "harness/runner.h"
#include "harness/shards.h"
#include "harness/stats.h"
#include "harness/subprocess.h"
#include "mesh/mesh_io.h"
#include "solvers/linear_solver.h"

namespace fs = std::filesystem;
using namespace db;
using namespace db::harness;

namespace {

constexpr double kMiB = 1024.0 * 1024.0;

// ------------------------------------------------------------------------------------------------ options
struct Options {
  std::string data = "data", results = "results", cache, scratch = fs::temp_directory_path().string();
  std::string thesis = "experiments/table_2_1_thesis.csv";
  bool full = false, scaling = true, out_of_core = true, dry_run = false;
  double memory_budget_mb = physical_memory_bytes() / 2.0 / kMiB, time_budget_s = 0, cell_timeout_s = 0;
  int frames = 20, repeats = 3;
  // Single runs of a cell's init vary by tens of percent within a day on a shared box (docs/experiments.md), hence the median
  // of fresh children; cells predicted to take longer than repeat_max_s (the --full scaling tiers) run once.
  double repeat_max_s = 40;
  std::vector<std::string> tiers, meshes, only, systems = {"lap", "tf"}, builds = {"dense", "naive", "structured"};
  std::vector<std::string> series, full_series;
  std::string backend = "multifrontal", dense_backend = "dense_llt", ordering = "default";
  ShardOptions shards;
};

void define_options(CLI::App& app, Options& o) {
  add_config_option(app, "data/experiments/table_2_1.toml");
  app.add_option("--data", o.data, "data directory; relative mesh paths of --tier and --series are inside it")
      ->capture_default_str();
  app.add_option("--results", o.results, "results directory")->capture_default_str();
  app.add_option("--tier", o.tiers, "a tier of the table: NAME=MESH[+loopK] (MESH relative to --data)")->delimiter(',');
  app.add_option("--mesh", o.meshes, "another tier, NAME=PATH[+loopK] (PATH as given): your own mesh");
  app.add_option("--only", o.only, "run only these tiers (labels, comma-separated)")->delimiter(',');
  app.add_option("--systems", o.systems, "systems")->delimiter(',')->check(cli::OneOf({"lap", "tf"}))->capture_default_str();
  app.add_option("--builds", o.builds, "builds")->delimiter(',')->check(cli::OneOf({"dense", "naive", "structured"}))
      ->capture_default_str();
  app.add_option("--backend", o.backend, "sparse builds' solver")->check(cli::OneOf(solver_names()))->capture_default_str();
  app.add_option("--dense-backend", o.dense_backend, "dense build's solver")->check(cli::OneOf(solver_names()))
      ->capture_default_str();
  app.add_option("--ordering", o.ordering, "fill-reducing ordering")->capture_default_str();
  app.add_option("--series", o.series, "scaling series of the structured build: NAME=MESH+loopA..B")->delimiter(',');
  app.add_option("--full-series", o.full_series, "levels --full adds to the series (same form)")->delimiter(',');
  app.add_flag("--full", o.full, "add --full-series; time budget 900 s a cell");
  app.add_flag("--dry-run", o.dry_run, "print the grid's cells (one spec a line) and exit");
  app.add_flag("!--no-scaling", o.scaling, "skip the scaling series");
  app.add_flag("!--no-out-of-core", o.out_of_core, "cells whose factor does not fit the budget are #over");
  app.add_option("--memory-budget-mb", o.memory_budget_mb, "memory budget per cell (default half the RAM)")
      ->check(cli::Real(1, 1e9));
  app.add_option("--time-budget-s", o.time_budget_s, "time budget per cell, predicted (default 120, --full 900)")
      ->check(cli::Real(0, 1e7));
  app.add_option("--cell-timeout-s", o.cell_timeout_s, "kill a running cell after this (default max(120, 3 x budget))")
      ->check(cli::Real(0, 1e7));
  app.add_option("--frames", o.frames, "frames of the drag")->transform(cli::Integer(1, 100000))->capture_default_str();
  app.add_option("--repeats", o.repeats, "fresh children per cell (median)")->transform(cli::Integer(1, 1000))
      ->capture_default_str();
  app.add_option("--repeat-max-s", o.repeat_max_s, "cells predicted above this run once")->check(cli::Real(0, 1e7))
      ->capture_default_str();
  app.add_option("--mesh-cache", o.cache, "where generated Loop levels go (default RESULTS/cells/meshes)");
  app.add_option("--scratch-dir", o.scratch, "out-of-core factors go here")->capture_default_str();
  app.add_option("--thesis", o.thesis, "the thesis' numbers (relative to --data)")->capture_default_str();
  add_shard_options(app, o.shards);
}

// Checks what can be checked before any work; fills the defaults that depend on other options.
void finish_options(Options& o) {
  check_output_dir("--results", o.results);
  if (o.cache.empty()) o.cache = (fs::path(o.results) / "cells" / "meshes").string();
  check_output_dir("--mesh-cache", o.cache);
  if (o.out_of_core && !fs::is_directory(o.scratch)) throw UsageError("--scratch-dir " + o.scratch + ": not a directory");
  if (fs::path(o.thesis).is_relative()) o.thesis = (fs::path(o.data) / o.thesis).string();
  if (!fs::exists(o.thesis)) throw UsageError("--thesis " + o.thesis + ": not found");
  if (o.time_budget_s <= 0) o.time_budget_s = o.full ? 900 : 120;
  if (o.cell_timeout_s <= 0) o.cell_timeout_s = std::max(120.0, 3 * o.time_budget_s);
  if (solver_info(o.dense_backend).family != "dense") throw UsageError("--dense-backend: not a dense solver");
}

std::vector<MeshSource> tier_sources(const Options& o) {
  std::vector<MeshSource> all;
  for (const auto& t : o.tiers) all.push_back(parse_mesh_source(t, o.data));
  for (const auto& m : o.meshes) all.push_back(parse_mesh_source(m, ""));
  if (all.empty()) throw UsageError("no tier: give --tier or --mesh (or a --config that lists them)");
  return select_sources(all, o.only);
}

// The series' meshes in order, --full's levels merged into their series.
std::vector<MeshSource> series_sources(const Options& o) {
  std::vector<MeshSource> all;
  auto add = [&](const std::string& text) {
    const auto levels = parse_mesh_series(text, o.data);
    auto pos = all.end();
    for (auto it = all.begin(); it != all.end(); ++it)
      if (it->series == levels.front().series) pos = it + 1;
    for (const auto& l : levels)
      if (std::none_of(all.begin(), all.end(), [&](const MeshSource& s) { return s.label == l.label; }))
        pos = all.insert(pos, l) + 1;
  };
  for (const auto& s : o.series) add(s);
  if (o.full)
    for (const auto& s : o.full_series) add(s);
  return all;
}

// ------------------------------------------------------------------------------------------------ cells
struct Record {
  std::string model, series;  // series: "" for Table 2-1 cells
  int level = 0;
  double vertices = std::nan("");
  DeformCell cell;
  CellResult res;
};

void log_record(const Record& rec) {
  const CellResult& r = rec.res;
  if (r.ok())
    std::cerr << fmt::format(
        "[table_2_1] {:34s} n={:8.0f} build {:7.3f} s  init {:7.3f} s  frame {:8.4f} s  peak {:7.1f} MiB  "
        "held {:7.1f} MiB  factor {:7.1f} MiB (pred {:7.1f})  wall {:.1f} s\n",
        rec.cell.key(), r.get("n"), r.get("build_s"), r.get("init_s"), r.get("frame_s"),
        r.get("peak_rss_bytes") / kMiB, r.get("held_total_bytes") / kMiB, r.get("factor_bytes") / kMiB,
        r.get("predicted_factor_bytes") / kMiB, r.get("cell_wall_s"));
  else
    std::cerr << fmt::format("[table_2_1] {:34s} {}: {}\n", rec.cell.key(), r.status, r.message);
}

// The child's answer as it came, for debugging a surprising number.
void write_raw_record(const std::string& results, const DeformCell& c, const CellResult& r, const std::string& basis) {
  try {
    const fs::path dir = fs::path(results) / "cells" / "table_2_1";
    fs::create_directories(dir);
    std::string name = c.key();
    std::replace(name.begin(), name.end(), '/', '_');
    write_atomically((dir / (name + ".txt")).string(), [&](std::ostream& out) {
      out << encode_result(r) << "\nexit: " << r.exit << "\nprediction basis: " << basis << "\n";
    });
  } catch (const std::exception&) {
  }
}

// One cell of the grid: where its mesh comes from (resolved when it runs) and the cell as it will run.
struct Planned {
  MeshSource src;
  DeformCell cell;
};

DeformCell cell_for(const Options& o, const MeshSource& src, const std::string& system, const std::string& build) {
  DeformCell c;
  c.model = src.label;
  c.mesh = src.levels ? fmt::format("{}+loop{}", src.path, src.levels) : src.path;
  set_deform_option(c.options, "method", system);
  set_deform_option(c.options, "build", build);
  set_deform_option(c.options, "backend", build == "dense" ? o.dense_backend : o.backend);
  if (build != "dense") set_deform_option(c.options, "ordering", o.ordering);  // the dense build orders nothing
  // thesis eq. 2-4: handle and anchors stay unknowns, K is #V x #V or 3#V x 3#V
  set_deform_option(c.options, "constraints", "soft");
  c.frames = o.frames;
  c.memory_budget_bytes = static_cast<std::size_t>(o.memory_budget_mb * kMiB);
  c.handle_frames = true;  // the handle-mode frame and precompute beside the thesis' frame (issue 16)
  return c;
}

//! The grid, a plain list: tiers x systems x builds, then the series' levels x {lap, tf} x structured.
std::vector<Planned> plan(const Options& o) {
  std::vector<Planned> g;
  for (const MeshSource& t : tier_sources(o))
    for (const auto& system : o.systems)
      for (const auto& build : o.builds) g.push_back({t, cell_for(o, t, system, build)});
  if (o.scaling)
    for (const MeshSource& s : series_sources(o))
      for (const char* system : {"lap", "tf"}) g.push_back({s, cell_for(o, s, system, "structured")});
  return g;
}

class TableRunner {
 public:
  TableRunner(const Options& o, const MachineRates& rates) : o_(o), rates_(rates) {}
  //! Runs a cell of the grid (or reuses one measured for another table on the same file).
  Record run(const Planned& p);

 private:
  void load(const MeshSource& src);
  void place_factor(DeformCell& c) const;
  CellResult run_one(const DeformCell& c) const;

  const Options& o_;
  MachineRates rates_;
  std::map<std::string, Record> done_;
  // The mesh of the cells now running, and its predictor.
  std::string source_, path_, load_error_;
  std::optional<Mesh> mesh_;
  std::unique_ptr<CellPredictor> predictor_;
};

void TableRunner::load(const MeshSource& src) {
  const std::string source = fmt::format("{}+loop{}", src.path, src.levels);
  if (source == source_) return;
  source_ = source;
  path_.clear();
  load_error_.clear();
  mesh_.reset();
  predictor_.reset();
  try {
    path_ = resolve_mesh(src, (fs::path(o_.data) / "generated").string(), o_.cache, self_executable());
    mesh_ = read_mesh(path_);
    predictor_ = std::make_unique<CellPredictor>(*mesh_, ThesisEditOptions{}, rates_);
  } catch (const std::exception& e) {
    load_error_ = e.what();
  }
}

Record TableRunner::run(const Planned& p) {
  load(p.src);
  Record rec{p.src.label, p.src.series, p.src.levels, mesh_ ? double(mesh_->num_vertices()) : std::nan(""), p.cell, {}};
  rec.cell.mesh = path_;
  // Keyed without the label: a tier and a series level may be the same file and the same cell.
  const std::string key = fmt::format("{}|{}|{}|{}|{}", path_, rec.cell.method(), rec.cell.build(), rec.cell.backend(),
                                      rec.cell.options.solver_options.ordering);
  if (auto it = done_.find(key); it != done_.end() && !path_.empty()) {
    rec.res = it->second.res;
    rec.cell.options.solver_options.factor_dir = it->second.cell.options.solver_options.factor_dir;  // where its
                                                                                                     // factor was kept
    return rec;
  }
  if (!load_error_.empty()) {
    rec.res = CellResult::with_status("error", load_error_);
  } else {
    place_factor(rec.cell);
    rec.res = run_one(rec.cell);
  }
  log_record(rec);
  done_[key] = rec;
  return rec;
}

// Out of core for a cell whose factor does not fit the memory budget: when its backend can keep the factor on
// disk, the rest fits the budget and the scratch directory has room for the factor. Otherwise the cell is left as
// it is (and will be #over).
void TableRunner::place_factor(DeformCell& c) const {
  const double budget = o_.memory_budget_mb * kMiB;
  if (!o_.out_of_core || c.options.build == Build::Dense || !solver_info(c.backend()).out_of_core) return;
  try {
    if (predictor_->predict(c).total_bytes <= budget) return;
    DeformCell d = c;
    d.options.solver_options.factor_dir = o_.scratch;
    const DeformPrediction q = predictor_->predict(d);
    const double free_bytes = static_cast<double>(fs::space(o_.scratch).available);
    if (q.total_bytes > budget || free_bytes < 1.05 * q.factor_bytes) {
      std::cerr << fmt::format("[table_2_1] {}: out of core does not fit either ({:.0f} MiB resident predicted; "
                               "{:.0f} MiB of factor for {:.0f} MiB free in {})\n",
                               c.key(), q.total_bytes / kMiB, q.factor_bytes / kMiB, free_bytes / kMiB, o_.scratch);
      return;
    }
    c = d;
  } catch (const std::exception&) {  // run_one reports a prediction that fails
  }
}

CellResult TableRunner::run_one(const DeformCell& c) const {
  DeformPrediction p;
  try {
    p = predictor_->predict(c);
  } catch (const std::exception& e) {
    return CellResult::with_status("error", std::string("prediction failed: ") + e.what());
  }
  const double budget = o_.memory_budget_mb * kMiB;
  RunOptions ro;
  ro.timeout_s = o_.cell_timeout_s;
  // Safety net for a wrong prediction: the child fails with bad_alloc instead of pushing the box into the OOM
  // killer (others share it). Virtual reservations (thread stacks, malloc arenas) need the slack; an out-of-core
  // factor's file mapping is address space too.
  ro.address_space_bytes = static_cast<std::size_t>(std::max(1.5 * budget, budget + 4.0 * (1 << 30)) +
                                                    (c.factor_storage() == "memory" ? 0.0 : p.factor_bytes));
  ro.repeats = o_.repeats;
  ro.repeat_max_s = o_.repeat_max_s;
  ro.machine_rates = true;
  ro.memory_budget_bytes = budget;
  ro.time_budget_s = o_.time_budget_s;
  const Prediction g = p.generic();
  const CellResult r = run_cell(self_executable(), c.to_spec(), ro, &g);
  write_raw_record(o_.results, c, r, p.basis);
  return r;
}

// ------------------------------------------------------------------------------------------------ CSV
// The schema of table_2_1.csv and scaling.csv: every cell keeps the Always rows, so every (model, system, build)
// has the same rows whether it ran or not; each timing is followed by its spread (core/spread.h spread_name).
const std::vector<MeasureDef>& table_measures() {
  static const std::vector<MeasureDef> d = {
      {"vertices", "count"}, {"n", "count"}, {"nnz", "count"}, {"nnz_factor", "count"}, {"factor_flops", "flop"},
      {"min_pivot_ratio", "ratio"}, {"build_s", "s", Keep::Always}, {"analyze_s", "s", Keep::Always},
      {"factorize_s", "s", Keep::Always}, {"init_s", "s", Keep::Always}, {"frames", "count"},
      {"frame_s", "s", Keep::Always}, {"rhs_s", "s"}, {"solve_s", "s"}, {"write_s", "s"},
      {"fps", "1/s", Keep::Always}, {"precompute_s", "s", Keep::Always}, {"precompute_cpu_s", "s"},
      {"init_precompute_s", "s", Keep::Always},
      {"frame_handle_s", "s", Keep::Always}, {"response_s", "s"}, {"fps_handle", "1/s", Keep::Always},
      {"response_bytes", "bytes"}, {"handle_vs_full", "bbox_diagonal"}, {"peak_rss_handle_bytes", "bytes"},
      {"matrix_bytes", "bytes", Keep::Always}, {"factor_bytes", "bytes", Keep::Always},
      {"held_total_bytes", "bytes", Keep::Always}, {"peak_rss_bytes", "bytes", Keep::Always},
      {"baseline_rss_bytes", "bytes"}, {"mean_displacement", "bbox_diagonal"}, {"ru_maxrss_bytes", "bytes"},
      {"parent_rss_bytes", "bytes"}, {"cell_wall_s", "s"}, {"runs", "count"}, {"held_bytes:*", "bytes"},
      {"predicted_build_bytes", "bytes", Keep::Always}, {"predicted_factor_bytes", "bytes", Keep::Always},
      {"predicted_workspace_bytes", "bytes", Keep::Always}, {"predicted_bytes", "bytes", Keep::Always},
      {"predicted_factor_nnz", "count", Keep::Always}, {"predicted_factor_flops", "flop", Keep::Always},
      {"predicted_s", "s", Keep::Always, false},
      // The machine's speed around the cell, for telling a slow machine from a slow code.
      {"blas_dgemm_before", "GFlop/s", Keep::IfMeasured}, {"memory_read_before", "GB/s", Keep::IfMeasured},
      {"blas_dgemm_after", "GFlop/s", Keep::IfMeasured}, {"memory_read_after", "GB/s", Keep::IfMeasured},
  };
  return d;
}

void add_long_rows(CsvTable& csv, const Record& rec, bool with_series) {
  CsvTable::Row key;
  if (with_series) key.insert(key.end(), {{"series", rec.series}, {"level", std::to_string(rec.level)}});
  key.insert(key.end(), {{"model", rec.model},
                         {"vertices", std::isnan(rec.vertices) ? "" : fmt::format("{}", rec.vertices)},
                         {"system", rec.cell.method()},
                         {"build", rec.cell.build()},
                         {"backend", rec.cell.backend()},
                         {"factor_storage", rec.cell.factor_storage()},
                         {"ordering_used", rec.res.text("ordering_used")}});
  add_measure_rows(csv, key, rec.res, table_measures());
}

void write_long_csv(const std::string& path, const std::vector<Record>& recs, bool with_series) {
  CsvTable csv;
  for (const auto& r : recs) add_long_rows(csv, r, with_series);
  if (!csv.empty()) csv.write(path);
}

// The thesis' numbers (a data file) with this run's provenance, beside the measured table for the report.
void write_thesis_csv(const Options& o) {
  CsvTable csv;
  for (const CsvRow& r : read_csv(o.thesis)) {
    CsvTable::Row row;
    for (const char* k : {"model", "thesis_model", "vertices", "system", "stage", "measure", "value", "unit", "status",
                          "source"}) {
      auto it = r.find(k);
      if (it == r.end()) throw InputError(fmt::format("{}: no column '{}'", o.thesis, k));
      row.emplace_back(k, it->second);
    }
    csv.add(std::move(row));
  }
  csv.write((fs::path(o.results) / "table_2_1_thesis.csv").string());
}

// ------------------------------------------------------------------------------------------------ scaling fits
struct FitRow {
  std::string series, system, measure;
  PowerFit fit;
  double nmin = 0, nmax = 0;
};

// Cost ~ c * #V^k per series (and over all of them) for one system and measure.
std::optional<FitRow> fit_one(const std::vector<Record>& recs, const std::string& series, const std::string& system,
                              const std::string& m) {
  std::vector<double> x, y;
  // Out of core the factor is not resident and the frames read it back from the page cache: that peak and that
  // frame time are not the same quantities, so only in-memory cells enter their fits.
  const bool in_memory_only = m == "peak_rss_bytes" || m == "frame_s";
  for (const auto& r : recs)
    if ((series == "all" || r.series == series) && r.cell.method() == system && r.res.ok() &&
        !(in_memory_only && r.cell.factor_storage() == "disk") &&
        std::find(x.begin(), x.end(), r.vertices) == x.end()) {  // "all" would count shared cells twice
      x.push_back(r.vertices);
      y.push_back(r.res.get(m));
    }
  const PowerFit f = fit_power_law(x, y);
  if (std::isnan(f.exponent)) return std::nullopt;  // fewer than kMinFitPoints points: no fit
  return FitRow{series, system, m, f, *std::min_element(x.begin(), x.end()), *std::max_element(x.begin(), x.end())};
}

std::vector<FitRow> fit_series(const std::vector<Record>& recs) {
  std::vector<std::string> series;
  for (const auto& r : recs)
    if (std::find(series.begin(), series.end(), r.series) == series.end()) series.push_back(r.series);
  series.push_back("all");
  std::vector<FitRow> fits;
  for (const auto& s : series)
    for (const char* system : {"lap", "tf"})
      for (const char* m : {"init_s", "build_s", "factorize_s", "frame_s", "factor_bytes", "peak_rss_bytes"})
        if (auto f = fit_one(recs, s, system, m)) fits.push_back(*f);
  return fits;
}

void write_fits(const std::string& path, const std::vector<FitRow>& fits) {
  CsvTable f;
  for (const auto& x : fits)
    f.add({{"series", x.series},
           {"system", x.system},
           {"build", "structured"},
           {"measure", x.measure},
           {"exponent", num(x.fit.exponent)},
           {"coefficient", num(x.fit.coefficient)},
           {"r2", num(x.fit.r2)},
           {"points", std::to_string(x.fit.points)},
           {"vertices_min", num(x.nmin)},
           {"vertices_max", num(x.nmax)}});
  if (!f.empty()) f.write(path);
}

// ------------------------------------------------------------------------------------------------ the run
std::vector<std::pair<std::string, std::string>> settings(const Options& o, const MachineRates& rates) {
  return {{"memory_budget_bytes", num(o.memory_budget_mb * kMiB)},
          {"time_budget_s", num(o.time_budget_s)},
          {"cell_timeout_s", num(o.cell_timeout_s)},
          {"frames", std::to_string(o.frames)},
          {"repeats", std::to_string(o.repeats)},
          {"repeat_max_s", num(o.repeat_max_s)},
          {"backend", o.backend},
          {"dense_backend", o.dense_backend},
          {"ordering", o.ordering},
          {"rate_dense_flops", num(rates.dense)},
          {"rate_sparse_flops", num(rates.sparse)},
          {"rate_stream_flops", num(rates.stream)},
          {"full", o.full ? "yes" : "no"}};
}

// One line per tier for the report: where its mesh came from and where the thesis edit put handle and anchors.
std::string edit_note(const std::string& path) {
  try {
    const Mesh m = read_mesh(path);
    return fmt::format("{} ({} vertices): {}", path, m.num_vertices(), describe_thesis_edit(m));
  } catch (const std::exception& e) {
    return e.what();
  }
}

// Runs the grid; the CSVs are rewritten after every mesh: an interrupted run keeps what it measured. Failed cells
// are noted in `failed` (a failed cell's rows are written like any other's).
void run_grid(const Options& o, const std::vector<Planned>& grid, TableRunner& runner,
              std::vector<std::pair<std::string, std::string>>& notes, FailedCells& failed) {
  const fs::path dir(o.results);
  std::vector<Record> table, scaling;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    Record r = runner.run(grid[i]);
    failed.note(r.cell.to_spec().text(), r.res);
    const bool last_of_mesh = i + 1 == grid.size() || grid[i + 1].cell.mesh != grid[i].cell.mesh ||
                              grid[i + 1].src.series != grid[i].src.series;
    if (!r.series.empty()) {
      scaling.push_back(std::move(r));
      if (last_of_mesh) write_long_csv((dir / "scaling.csv").string(), scaling, true);
      continue;
    }
    if (last_of_mesh && !r.cell.mesh.empty()) notes.emplace_back("edit:" + r.model, edit_note(r.cell.mesh));
    table.push_back(std::move(r));
    if (last_of_mesh) write_long_csv((dir / "table_2_1.csv").string(), table, false);
  }
  if (!o.scaling) return;
  for (const auto& r : table)
    if (r.cell.options.build == Build::Structured) {
      Record x = r;
      x.series = "tiers";
      scaling.push_back(x);
    }
  write_long_csv((dir / "scaling.csv").string(), scaling, true);
  write_fits((dir / "scaling_fits.csv").string(), fit_series(scaling));
}

// ------------------------------------------------------------------------------------------------ shards
// A cell's group: the cells of one mesh (a tier's, or a series level's), which share the loaded mesh and its
// predictor. A tier and a series level of the same file are two groups; in two shards that cell is measured twice.
std::string group_of(const Planned& p) {
  return p.src.series.empty() ? "tier|" + p.src.label : "series|" + p.src.series + "|" + p.src.label;
}

// The cells of scaling.csv rows back from the CSV (consecutive rows of one cell), as far as the fits read them.
std::vector<Record> scaling_records(const std::string& path) {
  std::vector<Record> recs;
  std::string last;
  for (const CsvRow& row : read_csv(path)) {
    const std::string key = row.at("series") + "|" + row.at("level") + "|" + row.at("model") + "|" +
                            row.at("system") + "|" + row.at("build");
    if (recs.empty() || key != last) {
      Record r;
      r.series = row.at("series");
      r.model = row.at("model");
      r.vertices = row.at("vertices").empty() ? std::nan("") : std::stod(row.at("vertices"));
      set_deform_option(r.cell.options, "method", row.at("system"));
      set_deform_option(r.cell.options, "build", row.at("build"));
      if (row.at("factor_storage") == "disk") r.cell.options.solver_options.factor_dir = "disk";
      r.res.status = row.at("status");
      recs.push_back(std::move(r));
      last = key;
    }
    if (!row.at("value").empty()) recs.back().res.set(row.at("measure"), std::stod(row.at("value")), row.at("unit"));
  }
  return recs;
}

// --merge-shards N: the shards' table_2_1.csv and scaling.csv in grid order, the fits refitted from the merged
// scaling rows, the thesis' numbers, shard 1's settings.
int merge_shards(Options& o, const std::vector<Planned>& grid) {
  const int n = o.shards.merge;
  const fs::path dir(o.results);
  std::vector<std::string> table, series, tiers;
  for (const Planned& p : grid) {
    std::vector<std::string>& v = p.src.series.empty() ? table : series;
    if (v.empty() || v.back() != group_of(p)) v.push_back(group_of(p));
    if (p.src.series.empty() && (tiers.empty() || tiers.back() != "tiers|" + p.src.label))
      tiers.push_back("tiers|" + p.src.label);
  }
  merge_shard_csv(o.results, n, "table_2_1.csv", (dir / "table_2_1.csv").string(), table,
                  [](const CsvRow& r) { return "tier|" + r.at("model"); });
  if (o.scaling) {
    series.insert(series.end(), tiers.begin(), tiers.end());  // the structured table rows, appended last
    merge_shard_csv(o.results, n, "scaling.csv", (dir / "scaling.csv").string(), series, [](const CsvRow& r) {
      return r.at("series") == "tiers" ? "tiers|" + r.at("model") : "series|" + r.at("series") + "|" + r.at("model");
    });
    write_fits((dir / "scaling_fits.csv").string(), fit_series(scaling_records((dir / "scaling.csv").string())));
  }
  write_thesis_csv(o);
  std::vector<std::pair<std::string, std::string>> notes;
  for (const CsvRow& r : read_csv((fs::path(shard_directory(o.results, 1, n)) / "table_2_1_settings.csv").string()))
    notes.emplace_back(r.at("setting"), r.at("value"));
  notes.emplace_back("shards", std::to_string(n));
  write_settings((dir / "table_2_1_settings.csv").string(), notes);
  std::cerr << fmt::format("[table_2_1] merged {} shards into {}\n", n, o.results);
  return 0;
}

// --shard I/N: the shard's cells of the grid; its outputs go to RESULTS/shards/I-of-N/.
std::vector<Planned> shard_of(Options& o, const std::vector<Planned>& grid) {
  const Shard s = o.shards.parsed();
  if (!s.active()) return grid;
  o.results = shard_directory(o.results, s.index, s.count);
  return shard_slice(grid, s, group_of);
}

int run(Options& o) {
  finish_options(o);
  const std::vector<Planned> all = plan(o);  // the tiers and series are checked before any work
  if (o.shards.merge > 0) return merge_shards(o, all);
  const std::vector<Planned> grid = shard_of(o, all);
  if (o.dry_run) {
    for (const Planned& p : grid) std::cout << p.cell.to_spec().text() << "\n";
    return 0;
  }
  fs::create_directories(o.results);
  std::cerr << "[table_2_1] " << provenance_summary() << "\n";
  const MachineRates rates = MachineRates::measure();
  std::cerr << fmt::format("[table_2_1] rates: dense {:.2f} GFlop/s, sparse {:.3f} GFlop/s, stream {:.2f} GFlop/s; "
                           "budgets {:.0f} MiB, {:.0f} s per cell\n",
                           rates.dense / 1e9, rates.sparse / 1e9, rates.stream / 1e9, o.memory_budget_mb, o.time_budget_s);
  TableRunner runner(o, rates);
  write_thesis_csv(o);
  auto notes = settings(o, rates);
  FailedCells failed("table_2_1");
  run_grid(o, grid, runner, notes, failed);
  write_settings((fs::path(o.results) / "table_2_1_settings.csv").string(), notes);
  std::cerr << "[table_2_1] wrote " << o.results << "/table_2_1.csv" << (o.scaling ? ", scaling.csv, scaling_fits.csv" : "")
            << "\n";
  return failed.exit_code();
}

}  // namespace

int main(int argc, char** argv) {
  if (is_cell_invocation(argc, argv)) return cell_main(argc, argv, {deform_kind(), loop_subdivide_kind()});
  CLI::App app("Thesis Table 2-1: dense, naive and structured builds of LAP and TF on the tiers of a config; "
               "cells in fresh child processes under memory and time budgets.",
               "exp_table_2_1");
  Options o;
  define_options(app, o);
  return cli::run(app, argc, argv, [&] { return run(o); });
}
