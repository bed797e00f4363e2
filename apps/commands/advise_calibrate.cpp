// deformbench advise --calibrate: the rates methods/run_prediction.h turns counts into seconds and bytes with,
// measured on this machine. Generated planes (mesh/procedural.h) are deformed by every backend in fresh children
// (`deformbench deform --csv`), each run set against its own prediction; two sizes give the factorization's rate
// and how it grows with the work. Kept in calibration_path() with the provenance of the runs.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <unistd.h>

#include "core/child_process.h"
#include "core/csv_reader.h"
#include "core/provenance.h"
#include "edit/edit_io.h"
#include "mesh/mesh_io.h"
#include "mesh/procedural.h"
#include "methods/deform_options.h"
#include "methods/run_prediction.h"
#include "solvers/base/error.h"
#include "solvers/linear_solver.h"

namespace db::commands {
namespace {

namespace fs = std::filesystem;

//! One calibration run: a backend, a build, a method on a generated plane of `cells` x `cells` squares.
struct CalibrationRun {
  std::string backend, build, method;
  int cells = 0;
};

// Sparse backends on TF (the 3x3 blocks), at two sizes; the naive build once; the dense backends on small LAP
// systems (n^3) with the dense and the structured build.
std::vector<CalibrationRun> calibration_runs() {
  std::vector<CalibrationRun> runs;
  for (const char* b : {"multifrontal", "cholmod_supernodal", "cholmod_simplicial_ldlt", "eigen_simplicial_llt",
                        "eigen_simplicial_ldlt", "umfpack", "eigen_sparse_lu", "mumps", "multifrontal_mixed",
                        "multifrontal_refined", "cg_ichol", "cg_jacobi"})
    for (int cells : {60, 100}) runs.push_back({b, "structured", "tf", cells});
  for (int cells : {60, 100}) runs.push_back({"multifrontal", "naive", "tf", cells});
  for (const char* b : {"dense_llt", "lapack_potrf"})
    for (const char* build : {"dense", "structured"})
      for (int cells : {40, 60}) runs.push_back({b, build, "lap", cells});
  return runs;
}

//! The .edit of a generated plane: the whole mesh free, 50 vertices at a corner dragged up.
std::string write_plane_edit(const std::string& dir, int cells) {
  const Mesh plane = make_bumpy_plane(cells, cells, 1.0, 0.05, 3);
  const std::string stem = fmt::format("{}/plane{}", dir, cells);
  write_mesh(stem + ".off", plane);
  std::ofstream(stem + ".edit") << fmt::format(
      "mesh = plane{}.off\nroi = all\nhandle = nearest:{},{},{},50\ntransform = translate:0,0,0.1\n", cells,
      plane.V(0, 0), plane.V(0, 1), plane.V(0, 2));
  return stem + ".edit";
}

//! One run's rates (the exponent is set from the two sizes afterwards); false when the child failed.
bool measure_run(const CalibrationRun& run, const std::string& edit, double timeout_s, BackendRates& r) {
  const EditCase ec = load_edit_case(edit);
  DeformOptions o;
  set_deform_option(o, "method", run.method);
  set_deform_option(o, "constraints", "soft");
  set_deform_option(o, "build", run.build);
  o.solver = run.backend;
  if (run.backend == "multifrontal_mixed") set_deform_option(o, "precision", "mixed");
  const RunPrediction p = predict_run(ec.mesh, ec.edit, resolve_options(o), MachineCalibration{}, 1, true);
  const std::string csv = edit + "." + run.backend + "." + run.build + ".csv";
  std::vector<std::string> argv = {self_executable(), "deform", edit, "--method", run.method, "--constraints", "soft",
                                   "--build", run.build, "--solver", run.backend, "--out", edit + ".out.off",
                                   "--csv", csv};
  if (run.backend == "multifrontal_mixed") argv.insert(argv.end(), {"--precision", "mixed"});
  const ChildRun c = run_child(argv, timeout_s);
  fmt::print(stderr, "[calibrate] {} {} {} on plane{}: {}\n", run.backend, run.build, run.method, run.cells,
             c.ok() ? fmt::format("{:.2f} s", c.wall_s) : c.describe());
  if (!c.ok()) return false;
  const CsvRow row = read_csv(csv).at(0);
  auto get = [&](const char* k) { return std::stod(row.at(k)); };
  const double units = p.factor_flops > 0 ? p.factor_flops : p.nnz_matrix;
  r.factor_units = units;
  r.factor_s_per_unit = get("factorize_s") / units;
  r.analyze_ratio = p.analysis_s > 0 ? get("analyze_s") / p.analysis_s : 0;
  r.build_s_per_unit = get("build_s") / p.build_flops;
  const double held = p.factor_bytes + p.workspace_bytes;
  r.peak_per_factor = held > 0 ? std::max(0.1, (get("peak_rss_bytes") - p.base_bytes - p.build_bytes) / held) : 1;
  return true;
}

}  // namespace

int calibrate_machine(const std::string& path, double timeout_s) {
  const std::string dir = (fs::temp_directory_path() / fmt::format("deformbench-calibrate-{}", ::getpid())).string();
  fs::create_directories(dir);
  MachineCalibration cal;
  std::map<std::string, BackendRates> small;  // the first size's rates, per key
  for (const CalibrationRun& run : calibration_runs()) {
    BackendRates r;
    if (!measure_run(run, write_plane_edit(dir, run.cells), std::min(timeout_s, 120.0), r)) continue;
    const std::string key = run.backend + "/" + run.build;
    if (!small.count(key)) {
      small[key] = r;
      cal.rates[key] = r;
      continue;
    }
    const BackendRates& s = small[key];
    const double rate_ratio = (s.factor_s_per_unit / r.factor_s_per_unit);
    r.factor_exponent = std::clamp(std::log(rate_ratio) / std::log(r.factor_units / s.factor_units), 0.0, 0.5);
    cal.rates[key] = r;  // the larger size's rates, with the exponent between the two
  }
  fs::remove_all(dir);
  if (cal.empty()) throw SolverError("advise --calibrate: no calibration run succeeded");
  cal.provenance = provenance_summary() + " | " + provenance().timestamp;
  cal.save(path);
  fmt::print("wrote {} ({} backend/build rates)\n", path, cal.rates.size());
  return 0;
}

}  // namespace db::commands
