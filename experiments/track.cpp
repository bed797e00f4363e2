// The regression-tracking suite (issue 15): the cells of a config (data/experiments/track.toml: deformation cells
// of every method and build on three tiers, each solver backend's factorize / solve) run in fresh child processes
// (harness/runner.h), `--repeats` rounds over the whole suite (a cell's key rounds=N: the first N only), so a slow
// window of this shared machine touches one repeat of many cells rather than every repeat of one. Everything runs
// single-threaded, so that each phase's CPU time (harness/cpu_timer.h) is its own work: the time the gate compares.
// Between consecutive cells the driver measures the BLAS dgemm and memory read rates (harness/machine_rates.h):
// each run of a cell gets the rates just before and just after it, by which the gate normalizes wall times.
//
// Writes one tidy history file (--out, or HISTORY_DIR/<UTC>_<commit>_<machine>.csv): a row per (cell, measure,
// repeat) with the commit, date, machine id, the measure's class (deterministic: compared exactly; memory: peak
// RSS; cpu: CPU time; time: wall time, normalized by `rate`; info) and the rates around that run. Deterministic
// measures are recorded once. python/dbtools/track/driver.py (./run track) runs this, picks a baseline history and gates. Options: --help.
// Exits with kCellsFailedExit (harness/driver.h) when a cell failed, after writing the history.
#include <fnmatch.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <numeric>

#include <fmt/format.h>

#include "core/cli.h"
#include "core/csv.h"
#include "solvers/base/error.h"
#include "core/provenance.h"
#include "solvers/base/resources.h"
#include "harness/budget.h"
#include "harness/cell_pattern.h"
#include "harness/deform_cell.h"
#include "harness/driver.h"
#include "harness/machine_rates.h"
#include "harness/mesh_source.h"
#include "harness/runner.h"
#include "harness/solver_cell.h"
#include "harness/subprocess.h"
#include "mesh/mesh_io.h"
#include "solvers/linear_solver.h"

namespace fs = std::filesystem;
using namespace db;
using namespace db::harness;

namespace {

// ------------------------------------------------------------------------------------------------ options
struct Options {
  std::string data = "data", out, history_dir = "results/history/runs", commit, cache = "results/cells/meshes";
  std::vector<std::string> tiers, cells, defaults, overrides, only;
  int repeats = 5, rate_gemm_n = 512, rate_read_mb = 32;
  double cell_timeout_s = 600;
  bool dry_run = false, machine_id = false;
};

void define_options(CLI::App& app, Options& o) {
  add_config_option(app, "data/experiments/track.toml");
  app.add_option("--data", o.data, "data directory; tier paths are inside it")->capture_default_str();
  app.add_option("--tier", o.tiers, "a tier: NAME=MESH[+loopK] (MESH relative to --data)")->delimiter(',');
  app.add_option("--cells", o.cells, "cell patterns: 'KIND TIER[,TIER]: key=v1[,v2] ...' (harness/cell_pattern.h)");
  app.add_option("--default", o.defaults, "rules '[key=value ...]: key=value ...' setting keys a cell lacks");
  app.add_option("--override", o.overrides, "rules replacing keys of the cells they match (recorded in the history)");
  app.add_option("--only", o.only, "run only the cells whose name matches one of these globs")->delimiter(',');
  app.add_option("--repeats", o.repeats, "rounds over the suite (a cell's key rounds=N: only the first N; timed "
                 "measures need >= 5 for the gate)")
      ->transform(cli::Integer(1, 1000))->capture_default_str();
  app.add_option("--rate-gemm-n", o.rate_gemm_n, "the dgemm rate probe's matrix order (between every two cells)")
      ->transform(cli::Integer(64, 4096))->capture_default_str();
  app.add_option("--rate-read-mb", o.rate_read_mb, "the memory read rate probe's array, MB")
      ->transform(cli::Integer(1, 4096))->capture_default_str();
  app.add_option("--out", o.out, "the history file (default HISTORY_DIR/<UTC>_<commit>_<machine>.csv)");
  app.add_option("--history-dir", o.history_dir, "where the history file goes without --out")->capture_default_str();
  app.add_option("--commit", o.commit, "the commit measured (default: the source tree's, from provenance)");
  app.add_option("--cell-timeout-s", o.cell_timeout_s, "kill a cell after this")->check(cli::Real(1, 1e7))
      ->capture_default_str();
  app.add_option("--mesh-cache", o.cache, "where Loop levels the data step did not make are generated")
      ->capture_default_str();
  app.add_flag("--dry-run", o.dry_run, "print the suite's cells (name, then spec) and exit");
  app.add_flag("--machine-id", o.machine_id, "print this machine's id and its parts, and exit");
}

// ------------------------------------------------------------------------------------------------ machine id
// What decides whether timings compare: the processor, its cores, the memory, the BLAS kernels and the threads.
CsvTable::Row machine_parts() {
  const Provenance& p = provenance();
  return {{"machine_cpu", p.cpu},
          {"machine_cores", std::to_string(p.hardware_threads)},
          {"machine_ram_gib", fmt::format("{:.0f}", physical_memory_bytes() / 1073741824.0)},
          {"machine_blas_core", p.blas_core},
          {"machine_threads", fmt::format("{}/{}", p.blas_threads, p.build_threads)}};
}

// FNV-1a of the parts: short, stable across runs and builds.
std::string machine_id() {
  std::uint64_t h = 1469598103934665603ULL;
  for (const auto& [k, v] : machine_parts())
    for (const char c : k + "=" + v + ";") h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ULL;
  return fmt::format("{:012x}", h >> 16);
}

// ------------------------------------------------------------------------------------------------ the suite
struct Planned {
  std::string name;  // deform/TIER/METHOD/BUILD/BACKEND or solve/TIER/SYSTEM/BACKEND/ORDERING
  CellSpec spec;
  std::vector<Measure> predicted;  // parent-side deterministic measures (predicted bytes)
  int rounds = 0;                  // the rounds it runs in (the first ones): its key "rounds", else --repeats
  bool failed = false;
};

// The key "rounds" (a cell's own number of rounds, fewer than the suite's for its costliest cells) is the
// driver's, not the child's: taken out of the spec. 0 when absent.
int take_rounds(CellSpec& s) {
  if (!s.has("rounds")) return 0;
  const int rounds = static_cast<int>(s.integer("rounds", 0, 1, 1000));
  CellSpec rest;
  for (const auto& [k, v] : s.items())
    if (k != "rounds") rest.set(k, v);
  s = rest;
  return rounds;
}

std::map<std::string, std::string> tier_paths(const Options& o) {
  std::map<std::string, std::string> paths;
  for (const auto& t : o.tiers) {
    const MeshSource s = parse_mesh_source(t, o.data);
    if (paths.count(s.label)) throw UsageError(fmt::format("--tier: two tiers named '{}'", s.label));
    paths[s.label] = s.levels ? fmt::format("{}+loop{}", s.path, s.levels) : s.path;
  }
  return paths;
}

// Checks the keys and values of a spec as its child will, and names it.
std::string cell_name(const CellSpec& s) {
  if (s.kind() == "deform") {
    const DeformCell c = DeformCell::from_spec(s);
    solver_info(c.backend());
    return "deform/" + c.key();
  }
  if (s.kind() == "solve") {
    const SolverCell c = SolverCell::from_spec(s);
    solver_family(c.backend);
    return "solve/" + c.key();
  }
  throw UsageError(fmt::format("cell '{}': unknown kind (deform, solve)", s.text()));
}

bool selected(const Options& o, const std::string& name) {
  if (o.only.empty()) return true;
  return std::any_of(o.only.begin(), o.only.end(), [&](const std::string& g) { return ::fnmatch(g.c_str(), name.c_str(), 0) == 0; });
}

std::vector<Planned> plan(const Options& o) {
  const auto paths = tier_paths(o);
  std::vector<CellRule> defaults, overrides;
  for (const auto& d : o.defaults) defaults.push_back(parse_cell_rule(d));
  for (const auto& d : o.overrides) overrides.push_back(parse_cell_rule(d));
  std::vector<Planned> suite;
  for (const auto& pattern : o.cells)
    for (CellSpec s : expand_cell_pattern(pattern)) {
      auto tier = paths.find(s.get("model"));
      if (tier == paths.end()) throw UsageError(fmt::format("cell pattern '{}': no tier '{}'", pattern, s.get("model")));
      s.set("mesh", tier->second);
      for (const CellRule& r : defaults) apply_cell_rule(r, s, false);
      for (const CellRule& r : overrides) apply_cell_rule(r, s, true);
      const int rounds = take_rounds(s);
      const std::string name = cell_name(s);
      if (std::any_of(suite.begin(), suite.end(), [&](const Planned& p) { return p.name == name; }))
        throw UsageError(fmt::format("cell {} listed twice", name));
      if (selected(o, name)) suite.push_back({name, s, {}, rounds ? std::min(rounds, o.repeats) : o.repeats});
    }
  if (suite.empty()) throw UsageError("no cell to run (--cells, or --only matching none)");
  return suite;
}

// Generates the Loop levels a spec names (MESH+loopK) and puts the file's path in the spec.
void resolve_meshes(const Options& o, std::vector<Planned>& suite) {
  for (Planned& p : suite) {
    const std::string m = p.spec.get("mesh");
    const auto plus = m.rfind("+loop");
    if (plus == std::string::npos) continue;
    const MeshSource src{p.spec.get("model"), m.substr(0, plus), std::stoi(m.substr(plus + 5)), ""};
    p.spec.set("mesh", resolve_mesh(src, (fs::path(o.data) / "generated").string(), o.cache, self_executable()));
  }
}

// Predicted bytes (harness/budget.h) of the lap and tf deformation cells: deterministic, checked by the gate.
void predict(std::vector<Planned>& suite) {
  std::map<std::string, std::unique_ptr<CellPredictor>> predictors;
  std::map<std::string, Mesh> meshes;
  for (Planned& p : suite) {
    if (p.spec.kind() != "deform") continue;
    const DeformCell c = DeformCell::from_spec(p.spec);
    if (c.options.method == Method::Lri || c.mesh.empty()) continue;  // the predictor knows the lap and tf systems
    const std::string key = fmt::format("{}|{}|{}|{}", c.mesh, c.thesis.handle_count, c.thesis.anchor_count,
                                        c.thesis.drag_fraction);
    if (!predictors.count(key)) {
      meshes.emplace(key, read_mesh(c.mesh));
      predictors[key] = std::make_unique<CellPredictor>(meshes.at(key), c.thesis, MachineRates{});
    }
    p.predicted.push_back({"predicted_bytes", predictors[key]->predict(c).total_bytes, "bytes"});
  }
}

// ------------------------------------------------------------------------------------------------ measures
// What the history keeps of a cell, by class (deterministic, memory, cpu: gated; time: wall time, reported;
// info). rate: what the gate normalizes a wall time by (read: the memory read rate; dgemm: the BLAS dgemm rate;
// mixed: init_s = build_s + analyze_s at the read rate + factorize_s at dgemm's).
struct Tracked {
  const char* name;
  const char* cls;  // deterministic | memory | cpu | time | info
  const char* rate;
  const char* kinds;  // the cell kinds that report it
};

const std::vector<Tracked>& tracked_measures() {
  static const std::vector<Tracked> t = {
      {"n", "deterministic", "", "deform solve"},          {"nnz", "deterministic", "", "deform solve"},
      {"nnz_factor", "deterministic", "", "deform solve"}, {"factor_flops", "deterministic", "", "deform solve"},
      {"matrix_bytes", "deterministic", "", "deform solve"}, {"factor_bytes", "deterministic", "", "deform solve"},
      {"predicted_bytes", "deterministic", "", "deform"},  {"iterations", "deterministic", "", "solve"},
      {"peak_rss_bytes", "memory", "", "deform solve"},     {"build_s", "time", "read", "deform"},
      {"analyze_s", "time", "read", "deform solve"},       {"factorize_s", "time", "dgemm", "deform solve"},
      {"init_s", "time", "mixed", "deform"},               {"frame_s", "time", "read", "deform"},
      {"solve_s", "time", "read", "solve"},
      // CPU time of the child (harness/cpu_timer.h; cells run single-threaded): what the gate compares.
      {"init_cpu_s", "cpu", "", "deform"},       {"frame_cpu_s", "cpu", "", "deform"},
      {"build_cpu_s", "cpu", "", "solve"},       {"analyze_cpu_s", "cpu", "", "solve"},
      {"factorize_cpu_s", "cpu", "", "solve"},   {"solve_cpu_s", "cpu", "", "solve"},
      // The whole child, for the suite's own length: recorded, never gated.
      {"cell_wall_s", "info", "", "deform solve"}, {"cell_cpu_s", "info", "", "deform solve"},
  };
  return t;
}

bool reports(const Tracked& m, const std::string& kind) {
  return (" " + std::string(m.kinds) + " ").find(" " + kind + " ") != std::string::npos;
}

// ------------------------------------------------------------------------------------------------ the run
struct Rates {
  double dgemm = NAN, read = NAN;  // GFlop/s, GB/s
};

// Smaller probes than Table 2-1's (harness/machine_rates.h): they run between every two cells of every round.
Rates measure_rates(const Options& o) {
  return {MachineRates::blas_gemm(o.rate_gemm_n) / 1e9,
          MachineRates::read_bandwidth(std::size_t(o.rate_read_mb) << 20) / 1e9};
}

struct Run {
  std::string commit, date, machine, overrides;
  CsvTable::Row parts;
  CsvTable csv;
  std::map<std::string, double> first;  // deterministic values of round 1, by cell|measure
  int unstable = 0;
};

// The spec as the history keeps it: a path under the working directory (the repository, where ./run track
// runs this) relative to it, so that histories read the same in every clone.
std::string history_spec(const CellSpec& s) {
  const fs::path cwd = fs::current_path();
  CellSpec out;
  for (auto [key, value] : s.items()) {
    const fs::path rel = fs::path(value).lexically_relative(cwd);
    if (fs::path(value).is_absolute() && !rel.empty() && *rel.begin() != "..") value = rel.string();
    out.set(key, value);
  }
  return out.text();
}

void add_row(Run& run, const Planned& p, const Tracked& m, const Measure& v, int repeat, const Rates& before,
             const Rates& after, double load, const std::string& message = "") {
  CsvTable::Row row{{"commit", run.commit},  {"date", run.date},        {"machine_id", run.machine},
                    {"cell", p.name},        {"kind", p.spec.kind()},   {"tier", p.spec.get("model")},
                    {"measure", v.name},     {"class", m.cls},          {"rate", m.rate},
                    {"value", std::isnan(v.value) ? "" : num(v.value)}, {"unit", v.unit},
                    {"repeat", std::to_string(repeat)},
                    {"blas_dgemm_before", num(before.dgemm)},  {"blas_dgemm_after", num(after.dgemm)},
                    {"memory_read_before", num(before.read)},  {"memory_read_after", num(after.read)},
                    {"load_avg_1m", num(load)},  {"spec", history_spec(p.spec)}, {"overrides", run.overrides},
                    {"message", message}};
  row.insert(row.end(), run.parts.begin(), run.parts.end());
  run.csv.add(std::move(row));
}

// The rows of one run of a cell. Deterministic measures: round 1 only; later rounds are checked against it.
void record(Run& run, Planned& p, const CellResult& r, int repeat, const Rates& before, const Rates& after) {
  const double load = r.get("load_avg_1m");
  if (!r.ok()) {
    p.failed = true;
    add_row(run, p, {"status", "status", "", ""}, {"status", NAN, ""}, repeat, before, after, load,
            fmt::format("{}: {} ({})", r.status, r.message, r.exit));
    return;
  }
  for (const Tracked& m : tracked_measures()) {
    if (!reports(m, p.spec.kind())) continue;
    Measure v{m.name, NAN, ""};
    for (const Measure& q : r.measures)
      if (q.name == m.name) v = q;
    for (const Measure& q : p.predicted)
      if (q.name == m.name) v = q;
    if (std::isnan(v.value)) continue;
    const bool once = std::string(m.cls) == "deterministic";
    const std::string key = p.name + "|" + m.name;
    if (once && repeat > 1) {
      if (run.first.count(key) && run.first[key] != v.value) {
        ++run.unstable;
        std::cerr << fmt::format("[track] warning: {} {} was {} in round 1, {} in round {}\n", p.name, m.name,
                                 num(run.first[key]), num(v.value), repeat);
      }
      continue;
    }
    run.first[key] = v.value;
    add_row(run, p, m, v, repeat, before, after, load);
  }
}

std::string default_out(const Options& o, const Run& run) {
  std::string stamp = run.date;
  stamp.erase(std::remove_if(stamp.begin(), stamp.end(), [](char c) { return c == '-' || c == ':'; }), stamp.end());
  std::string commit = run.commit.substr(0, 12);
  std::replace(commit.begin(), commit.end(), '+', '_');
  return (fs::path(o.history_dir) / fmt::format("{}_{}_{}.csv", stamp, commit, run.machine)).string();
}

Run start_run(const Options& o) {
  Run run;
  run.commit = o.commit.empty() ? provenance().git_sha : o.commit;
  run.date = provenance().timestamp;
  run.machine = machine_id();
  run.parts = machine_parts();
  for (const auto& r : o.overrides) run.overrides += (run.overrides.empty() ? "" : "; ") + r;
  return run;
}

void log_cell(const Planned& p, const CellResult& r, int round) {
  if (!r.ok()) {
    std::cerr << fmt::format("[track] {} round {}: {} {} ({})\n", p.name, round, r.status, r.message, r.exit);
    return;
  }
  const double t = r.has("init_s") ? r.get("init_s") : r.get("factorize_s");
  std::cerr << fmt::format("[track] {:48s} round {}  {} {:8.4f} s  peak {:7.1f} MiB  wall {:.2f} s  cpu {:.2f} s\n",
                           p.name, round, r.has("init_s") ? "init     " : "factorize", t,
                           r.get("peak_rss_bytes") / 1048576.0, r.get("cell_wall_s"), r.get("cell_cpu_s"));
}

// `repeats` rounds over the suite, the machine rates measured between consecutive cells.
void run_rounds(const Options& o, std::vector<Planned>& suite, Run& run, FailedCells& failed) {
  RunOptions ro;
  ro.timeout_s = o.cell_timeout_s;
  Rates before = measure_rates(o);
  for (int round = 1; round <= o.repeats; ++round)
    for (Planned& p : suite) {
      if (p.failed || round > p.rounds) continue;
      const CellResult r = run_cell(self_executable(), p.spec, ro);
      failed.note(p.spec.text(), r);
      const Rates after = measure_rates(o);
      log_cell(p, r, round);
      record(run, p, r, round, before, after);
      before = after;
    }
}

int run(Options& o) {
  if (o.machine_id) {
    std::cout << machine_id() << "\n";
    for (const auto& [k, v] : machine_parts()) std::cout << k << "=" << v << "\n";
    return 0;
  }
  std::vector<Planned> suite = plan(o);
  if (o.dry_run) {
    for (const Planned& p : suite) std::cout << p.name << "  " << p.spec.text() << "  rounds=" << p.rounds << "\n";
    return 0;
  }
  Run run = start_run(o);
  const std::string out = o.out.empty() ? default_out(o, run) : o.out;
  if (o.out.empty()) check_output_dir("--history-dir", o.history_dir);
  else cli::check_output("--out", o.out, {".csv"});
  resolve_meshes(o, suite);
  predict(suite);
  const int runs = std::accumulate(suite.begin(), suite.end(), 0, [](int n, const Planned& p) { return n + p.rounds; });
  std::cerr << fmt::format("[track] {} cells, {} rounds, {} runs; machine {}; {}\n", suite.size(), o.repeats, runs,
                           run.machine, provenance_summary());
  FailedCells failed_cells("track");
  run_rounds(o, suite, run, failed_cells);
  if (!fs::path(out).parent_path().empty()) fs::create_directories(fs::path(out).parent_path());
  run.csv.write(out);
  const auto failed = std::count_if(suite.begin(), suite.end(), [](const Planned& p) { return p.failed; });
  std::cerr << fmt::format("[track] wrote {}{}{}\n", out, failed ? fmt::format("; {} cell(s) FAILED", failed) : "",
                           run.unstable ? fmt::format("; {} deterministic measure(s) varied", run.unstable) : "");
  std::cout << out << "\n";
  return failed_cells.exit_code();
}

// The suite runs single-threaded (BLAS, OpenMP, the structured assembly), so that a cell's CPU time is its own
// work and time-slicing by other processes does not enter it. The BLAS reads its thread count when it is loaded:
// the variables are set and the driver re-executed (its children inherit them).
// Returns only when it is (else exec failed: false).
bool run_single_threaded(char** argv) {
  const char* const vars[] = {"OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "DEFORMBENCH_THREADS"};
  if (std::all_of(std::begin(vars), std::end(vars), [](const char* v) {
        const char* e = std::getenv(v);
        return e && std::string(e) == "1";
      }))
    return true;
  for (const char* v : vars) ::setenv(v, "1", 1);
  ::execv(self_executable().c_str(), argv);
  std::cerr << fmt::format("exp_track: error: cannot re-execute {} single-threaded: {}\n", self_executable(),
                           std::strerror(errno));
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  if (is_cell_invocation(argc, argv))
    return cell_main(argc, argv, {deform_kind(), solver_kind(), loop_subdivide_kind()});
  if (!run_single_threaded(argv)) return 2;
  CLI::App app("The regression-tracking suite: its cells in fresh child processes, repeated in rounds, the machine "
               "rates measured around each; one tidy history file per run.",
               "exp_track");
  Options o;
  define_options(app, o);
  return cli::run(app, argc, argv, [&] { return run(o); });
}
