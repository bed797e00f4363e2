// deformbench advise --calibrate: the rates methods/run_prediction.h turns counts into seconds and bytes with,
// measured on this machine. Generated planes (mesh/procedural.h) are deformed by every backend in fresh children
// (`deformbench deform --csv`), each run set against its own prediction: two to four sizes per backend, build and
// method give each phase's time as a function of its work (PhaseRate) and the memory as a fixed part plus a
// multiple of the factor. Kept in calibration_path() with the provenance of the runs.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/child_process.h"
#include "core/csv_reader.h"
#include "core/enum_text.h"
#include "core/provenance.h"
#include "core/scratch_prefix.h"
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

//! One calibration run: a backend, a build, a method on a generated plane of `cells` x `cells` squares, with a
//! vertex ordering other than the default when `ordering` is set.
struct CalibrationRun {
  std::string backend, build, method;
  int cells = 0;
  std::string ordering;
};

//! Backends whose dense kernels run on fronts or supernodes that grow with the mesh.
bool grows_with_fronts(const std::string& backend) {
  return backend == "multifrontal" || backend == "multifrontal_mixed" || backend == "multifrontal_refined" ||
         backend == "cholmod_supernodal" || backend == "mumps";
}

// Every sparse backend on LAP and on TF, each at two sizes that bracket the solver study's meshes (LAP's unknowns
// are a third of TF's, so its planes are larger); the naive build likewise; the dense backends (n^3) on small
// systems with the dense and the structured build.
std::vector<CalibrationRun> calibration_runs() {
  std::vector<CalibrationRun> runs;
  auto both_methods = [&](const std::string& backend, const char* build) {
    // CG's iterations grow with the size: its larger LAP plane stays at TF's size
    const int lap_large = solver_info(backend).family == "iterative" ? 100 : 160;
    for (int cells : {40, lap_large}) runs.push_back({backend, build, "lap", cells, ""});
    for (int cells : {40, 100}) runs.push_back({backend, build, "tf", cells, ""});
    // the supernodal and multifrontal factorizations' rate still grows at TF's larger size: larger planes (30k
    // and 90k vertices) set how it levels off, so that the last segment, which extrapolates to larger meshes, is
    // measured near them
    if (std::string(build) == "structured" && grows_with_fronts(backend))
      for (int cells : {200, 300}) runs.push_back({backend, build, "tf", cells, ""});
  };
  for (const char* b : {"multifrontal", "cholmod_supernodal", "cholmod_simplicial_ldlt", "eigen_simplicial_llt",
                        "eigen_simplicial_ldlt", "umfpack", "eigen_sparse_lu", "mumps", "multifrontal_mixed",
                        "multifrontal_refined", "cg_ichol", "cg_jacobi"})
    both_methods(b, "structured");
  both_methods("multifrontal", "naive");
  // The structured build orders the vertex graph itself: AMD runs beside a one-thread build, METIS takes both cores
  // before the build takes them, so the build's and the analysis's costs differ by ordering: each method's other
  // ordering too (TF's up to a 40k-vertex plane, nearer the meshes its build and analysis extrapolate to)
  for (const char* b : {"multifrontal", "cholmod_supernodal"}) {
    for (int cells : {40, 160}) runs.push_back({b, "structured", "lap", cells, "metis"});
    for (int cells : {40, 100, 200}) runs.push_back({b, "structured", "tf", cells, "amd"});
  }
  for (const char* b : {"dense_llt", "lapack_potrf"})
    for (const char* build : {"dense", "structured"}) {
      for (int cells : {40, 60}) runs.push_back({b, build, "lap", cells, ""});
      for (int cells : {20, 30}) runs.push_back({b, build, "tf", cells, ""});
    }
  return runs;
}

//! What one run measured against the counts its prediction made (uncalibrated).
struct Sample {
  double build_units = 0, build_s = 0, analyze_units = 0, analyze_s = 0, factor_units = 0, factor_s = 0;
  double held_bytes = 0;   //!< predicted factor + workspace bytes
  double extra_bytes = 0;  //!< peak RSS - predicted base - predicted build bytes
  double wall_s = 0;       //!< the child's
};

//! A run whose child takes less is measured kShortRepeats times and each field is the median: a phase of a few
//! milliseconds moves by half of itself from one run to the next, and the smallest planes set the rates that the
//! small meshes' predictions rest on.
constexpr double kShortRunS = 1;
constexpr int kShortRepeats = 3;

//! A generated plane's edit (the whole mesh free, 50 vertices at a corner dragged up), loaded, with its predictor.
struct Plane {
  std::string edit;
  EditCase ec;
  std::unique_ptr<RunPredictor> predictor;
};

void make_plane(const ScratchPrefix& scratch, int cells, std::map<int, std::unique_ptr<Plane>>& planes) {
  const Mesh mesh = make_bumpy_plane(cells, cells, 1.0, 0.05, 3);
  const std::string stem = scratch.path(fmt::format("plane{}", cells));
  write_mesh(stem + ".off", mesh);
  std::ofstream(stem + ".edit") << fmt::format(
      "mesh = {}.off\nroi = all\nhandle = nearest:{},{},{},50\ntransform = translate:0,0,0.1\n",
      fs::path(stem).filename().string(), mesh.V(0, 0), mesh.V(0, 1), mesh.V(0, 2));
  auto p = std::make_unique<Plane>();
  p->edit = stem + ".edit";
  p->ec = load_edit_case(p->edit);
  p->predictor = std::make_unique<RunPredictor>(p->ec.mesh, p->ec.edit);
  planes.emplace(cells, std::move(p));
}

//! Every plane of the runs, smallest first, each predictor made before any backend analysis runs here: the base of
//! a prediction (this process's resident bytes when its predictor is made) is then a fresh process's, as in
//! advise, not one grown by earlier analyses (MUMPS starts MPI in the analyzing process).
std::map<int, std::unique_ptr<Plane>> make_planes(const ScratchPrefix& scratch,
                                                  const std::vector<CalibrationRun>& runs) {
  std::vector<int> sizes;
  for (const CalibrationRun& r : runs) sizes.push_back(r.cells);
  std::sort(sizes.begin(), sizes.end());
  sizes.erase(std::unique(sizes.begin(), sizes.end()), sizes.end());
  std::map<int, std::unique_ptr<Plane>> planes;
  for (int cells : sizes) make_plane(scratch, cells, planes);
  return planes;
}

//! One run measured in a fresh child; false when the child failed.
bool measure_run(const CalibrationRun& run, Plane& plane, double timeout_s, Sample& m) {
  DeformOptions o;
  set_deform_option(o, "method", run.method);
  set_deform_option(o, "constraints", "soft");
  set_deform_option(o, "build", run.build);
  o.solver = run.backend;
  if (run.backend == "multifrontal_mixed") set_deform_option(o, "precision", "mixed");
  if (!run.ordering.empty()) o.solver_options.ordering = run.ordering;
  const RunPrediction p = plane.predictor->predict(resolve_options(o), MachineCalibration{}, 1, true);
  const std::string& edit = plane.edit;
  const std::string csv = fmt::format("{}.{}.{}.{}.{}.csv", edit, run.backend, run.build, run.method, run.ordering);
  std::vector<std::string> argv = {self_executable(), "deform", edit, "--method", run.method, "--constraints", "soft",
                                   "--build", run.build, "--solver", run.backend, "--out", edit + ".out.off",
                                   "--csv", csv};
  if (run.backend == "multifrontal_mixed") argv.insert(argv.end(), {"--precision", "mixed"});
  if (!run.ordering.empty()) argv.insert(argv.end(), {"--ordering", run.ordering});
  const ChildRun c = run_child(argv, timeout_s);
  fmt::print(stderr, "[calibrate] {} {} {}{} on plane{}: {}\n", run.backend, run.build, run.method,
             run.ordering.empty() ? "" : " " + run.ordering, run.cells,
             c.ok() ? fmt::format("{:.2f} s", c.wall_s) : c.describe());
  if (!c.ok()) return false;
  const CsvRow row = read_csv(csv).at(0);
  auto get = [&](const char* k) { return std::stod(row.at(k)); };
  m = {p.build_flops, get("build_s"), p.analysis_s, get("analyze_s"),
       p.factor_flops > 0 ? p.factor_flops : p.nnz_matrix, get("factorize_s"), p.factor_bytes + p.workspace_bytes,
       get("peak_rss_bytes") - p.base_bytes - p.build_bytes, c.wall_s};
  return true;
}

//! Each field's median over `s` (not empty).
Sample median_sample(std::vector<Sample> s) {
  std::vector<double Sample::*> fields = {&Sample::build_units, &Sample::build_s,     &Sample::analyze_units,
                                          &Sample::analyze_s,   &Sample::factor_units, &Sample::factor_s,
                                          &Sample::held_bytes,  &Sample::extra_bytes,  &Sample::wall_s};
  Sample m;
  for (double Sample::*f : fields) {
    std::vector<double> v;
    for (const Sample& x : s) v.push_back(x.*f);
    std::nth_element(v.begin(), v.begin() + (v.size() - 1) / 2, v.end());
    m.*f = v[(v.size() - 1) / 2];
  }
  return m;
}

//! One run, measured again while it is short (kShortRunS); false when its first child failed.
bool measure(const CalibrationRun& run, Plane& plane, double timeout_s, Sample& m) {
  std::vector<Sample> s(1);
  if (!measure_run(run, plane, timeout_s, s[0])) return false;
  for (int k = 1; k < kShortRepeats && s[0].wall_s < kShortRunS; ++k)
    if (Sample again; measure_run(run, plane, timeout_s, again)) s.push_back(again);
  m = median_sample(s);
  return true;
}

//! Memory: the line through the (held, extra) points of the smallest and largest size - its slope the bytes per
//! predicted factor byte, its intercept the fixed bytes - or through the origin and the largest size when that line
//! would have a negative slope or intercept.
void fit_memory(const std::vector<Sample>& s, BackendRates& r) {
  auto by_held = [](const Sample& x, const Sample& y) { return x.held_bytes < y.held_bytes; };
  const Sample& small = *std::min_element(s.begin(), s.end(), by_held);
  const Sample& big = *std::max_element(s.begin(), s.end(), by_held);
  if (big.held_bytes <= 0) return;
  double slope = big.extra_bytes / big.held_bytes, fixed = 0;
  if (big.held_bytes > small.held_bytes) {
    const double line = (big.extra_bytes - small.extra_bytes) / (big.held_bytes - small.held_bytes);
    const double intercept = big.extra_bytes - line * big.held_bytes;
    if (line > 0 && intercept >= 0) slope = line, fixed = intercept;
  }
  r.peak_per_factor = std::max(0.1, slope);
  r.peak_fixed_bytes = fixed;
}

//! A key's rates from its samples (one per size that ran).
BackendRates fit_rates(const std::vector<Sample>& s) {
  std::vector<std::pair<double, double>> build, analyze, factorize;
  for (const Sample& m : s) {
    build.emplace_back(m.build_units, m.build_s);
    analyze.emplace_back(m.analyze_units, m.analyze_s);
    factorize.emplace_back(m.factor_units, m.factor_s);
  }
  BackendRates r;
  r.build = PhaseRate::fit(build);
  r.analyze = PhaseRate::fit(analyze);
  r.factorize = PhaseRate::fit(factorize);
  fit_memory(s, r);
  return r;
}

}  // namespace

int calibrate_machine(const std::string& path, double timeout_s) {
  MachineCalibration cal;
  {
    const ScratchPrefix scratch("calibrate");
    const std::vector<CalibrationRun> runs = calibration_runs();
    auto planes = make_planes(scratch, runs);
    std::map<std::string, std::vector<Sample>> samples;  // per key, in the order measured
    for (const CalibrationRun& run : runs) {
      Sample m;
      if (!measure(run, *planes.at(run.cells), std::min(timeout_s, 120.0), m)) continue;
      samples[MachineCalibration::key(run.backend, parse_enum<Build>(run.build), parse_enum<Method>(run.method),
                                      run.ordering)]
          .push_back(m);
    }
    for (const auto& [key, s] : samples) cal.rates[key] = fit_rates(s);
  }
  if (cal.empty()) throw SolverError("advise --calibrate: no calibration run succeeded");
  cal.provenance = provenance_summary() + " | " + provenance().timestamp;
  cal.save(path);
  fmt::print("wrote {} ({} backend/build/method rates)\n", path, cal.rates.size());
  return 0;
}

}  // namespace db::commands
