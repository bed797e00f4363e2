// Deforms the edit cases of a config (data/experiments/deform_cases.toml: the BS08 survey cases, the bundled CGAL
// cactus edit) with each method and writes one tidy row per (case, method): sizes, phase times, median frame time
// over a handle drag, bytes, and the peak RSS of the cell, which runs in a fresh child process (harness/
// deform_cell.h with the library's default options). Every timing has its spread (core/spread.h spread_name); a
// failed cell is a row with its status, and the driver then exits with kCellsFailedExit (harness/driver.h). Options:
// --help.
#include <filesystem>
#include <iostream>

#include <fmt/format.h>

#include "core/cli.h"
#include "core/csv.h"
#include "solvers/base/error.h"
#include "core/provenance.h"
#include "mesh/mesh_io.h"
#include "harness/deform_cell.h"
#include "harness/driver.h"
#include "harness/mesh_source.h"
#include "harness/runner.h"
#include "harness/subprocess.h"

namespace fs = std::filesystem;
using namespace db;
using namespace db::harness;

namespace {

struct Options {
  std::string data = "data", out = "results/deform_cases.csv", meshes;
  std::vector<std::string> cases, methods = {"lap", "tf"};
  int frames = 20;
  double cell_timeout_s = 600;
  bool dry_run = false;
};

void define_options(CLI::App& app, Options& o) {
  add_config_option(app, "data/experiments/deform_cases.toml");
  app.add_option("--data", o.data, "data directory; case paths are inside it")->capture_default_str();
  app.add_option("--out", o.out, "the CSV")->capture_default_str();
  app.add_option("--meshes", o.meshes, "write each case's last frame here (CASE_METHOD.ply)");
  app.add_option("--case", o.cases, "a case: NAME=EDIT (a .edit file or a Botsch-Sorkine stem, relative to --data)")
      ->delimiter(',');
  app.add_option("--methods", o.methods, "methods")->delimiter(',')->check(cli::OneOf(enum_names<Method>()))
      ->capture_default_str();
  app.add_option("--frames", o.frames, "frames of the drag")->transform(cli::Integer(1, 100000))->capture_default_str();
  app.add_option("--cell-timeout-s", o.cell_timeout_s, "kill a cell after this")->check(cli::Real(1, 1e7))
      ->capture_default_str();
  app.add_flag("--dry-run", o.dry_run, "print the grid's cells (one spec a line) and exit");
}

// An edit is there when its .edit file or its stem's mesh is.
bool edit_exists(const std::string& path) {
  if (fs::exists(path)) return true;
  for (const std::string& ext : mesh_extensions())
    if (fs::exists(path + ext)) return true;
  return false;
}

void add_row(CsvTable& csv, const DeformCell& c, const CellResult& r) {
  auto count = [&](const char* m) { return num(r.get(m)); };
  CsvTable::Row row = {{"case", c.model},
           {"mesh", r.text("mesh")},
           {"vertices", count("vertices")},
           {"faces", count("faces")},
           {"handle", count("handle")},
           {"fixed", count("fixed")},
           {"method", c.method()},
           {"constraints", r.text("constraints")},
           {"build", r.text("build")},
           {"backend", r.text("backend")},
           {"ordering", r.text("ordering_used")},
           {"n", count("n")},
           {"nnz", count("nnz")},
           {"nnz_factor", count("nnz_factor")},
           {"frames", count("frames")}};
  // Each timing with its spread: the phases of init over the one run, the frame over the frames of the drag.
  for (const char* m : {"build_s", "analyze_s", "factorize_s", "init_s", "frame_s"}) {
    row.emplace_back(m, num(r.get(m)));
    add_spread_columns(row, r, m);
  }
  row.insert(row.end(), {{"matrix_bytes", count("matrix_bytes")},
                         {"factor_bytes", count("factor_bytes")},
                         {"process_peak_rss_bytes", count("peak_rss_bytes")},
                         {"status", r.status},
                         {"message", r.message}});
  csv.add(std::move(row));
}

CellResult run_one(const Options& o, const DeformCell& c, FailedCells& failed) {
  RunOptions ro;
  ro.timeout_s = o.cell_timeout_s;
  CellResult r = run_cell(self_executable(), c.to_spec(), ro);
  failed.note(c.to_spec().text(), r);
  if (!r.ok()) {
    std::cerr << fmt::format("[deform_cases] {} {}: {}: {} ({})\n", c.model, c.method(), r.status, r.message, r.exit);
    return r;
  }
  std::cerr << fmt::format("[deform_cases] {:14s} {:3s} n={:6.0f} init {:.3f} s  frame {:.4f} s  peak {:.1f} MiB\n",
                           c.model, c.method(), r.get("n"), r.get("init_s"), r.get("frame_s"),
                           r.get("peak_rss_bytes") / 1048576.0);
  return r;
}

int run(Options& o) {
  cli::check_output("--out", o.out, {".csv"});
  if (!o.meshes.empty()) check_output_dir("--meshes", o.meshes);
  std::vector<MeshSource> cases;
  for (const auto& text : o.cases) {
    MeshSource s = parse_mesh_source(text, o.data);
    if (edit_exists(s.path)) cases.push_back(s);
    else std::cerr << fmt::format("[deform_cases] skipping {}: {} not found (run scripts/data.sh)\n", s.label, s.path);
  }
  if (cases.empty()) throw InputError("no edit case found (--case, or a --config that lists cases)");
  std::vector<DeformCell> grid;  // a plain list: cases x methods
  for (const MeshSource& s : cases)
    for (const auto& method : o.methods) {
      DeformCell c;
      c.model = s.label;
      c.edit = s.path;
      set_deform_option(c.options, "method", method);
      c.frames = o.frames;
      if (!o.meshes.empty()) c.out_mesh = (fs::path(o.meshes) / fmt::format("{}_{}.ply", s.label, method)).string();
      grid.push_back(c);
    }
  if (o.dry_run) {
    for (const DeformCell& c : grid) std::cout << c.to_spec().text() << "\n";
    return 0;
  }
  if (!o.meshes.empty()) fs::create_directories(o.meshes);
  std::cerr << "[deform_cases] " << provenance_summary() << "\n";
  CsvTable csv;
  FailedCells failed("deform_cases");
  for (const DeformCell& c : grid) add_row(csv, c, run_one(o, c, failed));
  csv.write(o.out);
  std::cerr << "[deform_cases] wrote " << o.out << "\n";
  return failed.exit_code();
}

}  // namespace

int main(int argc, char** argv) {
  if (is_cell_invocation(argc, argv)) return cell_main(argc, argv, {deform_kind()});
  CLI::App app("The edit cases of a config with each method, every (case, method) in a fresh child process.",
               "exp_deform_cases");
  Options o;
  define_options(app, o);
  return cli::run(app, argc, argv, [&] { return run(o); });
}
