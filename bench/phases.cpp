// Google Benchmark suite for regression tracking of the four phases of a deformation's precompute / per-frame
// split: system build, solver analyze, factorize and solve, per (tier, system, build, backend).
//
// Names are stable (`./run track bench` gates them against results/bench/baseline.json):
//   build/mesh:armadillo/system:tf/build:structured
//   analyze/mesh:armadillo/system:tf/build:structured/backend:cholmod_supernodal
//   factorize/... solve/...  (same shape as analyze)
//   precompute/...  (same shape: the handle responses of handle-mode frames, one multi-right-hand-side solve)
//   frame_handle/mesh:armadillo/system:tf/build:structured  (one handle-mode frame: the responses streamed)
// Counters: n (unknowns), nnz (stored upper-triangle nonzeros of K), nnz_L (factor nonzeros) and bytes (build:
// bytes of the matrices the build held; solver phases: bytes of the factor).
//
// The system is the thesis edit of the tier (harness/thesis_edit.h) with soft constraints, so K is #V x #V (lap,
// 3 right-hand-side columns) or 3#V x 3#V (tf), in the mesh's vertex order; backends use their default ordering.
// Setup stays out of the timed region: meshes, operators and systems are built once per (tier, system, build)
// and cached; solve benchmarks reuse a factorized solver kept for the whole run; per-iteration setup (a fresh
// solver for analyze, freeing the previous build) runs with the timer paused. No manual time, so the names carry
// no "/manual_time" suffix.
//
// Own options: `bench_phases --help`; Google Benchmark's flags pass through to it.
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include "core/cli.h"
#include "solvers/base/error.h"
#include "core/provenance.h"
#include "harness/thesis_edit.h"
#include "mesh/mesh_io.h"
#include "methods/deformer.h"
#include "methods/normalization.h"
#include "operators/energy_operator.h"
#include "solvers/linear_solver.h"
#include "systems/normal_system.h"

namespace fs = std::filesystem;
using namespace db;

namespace {

// Everything a (tier, system) needs before a build: the mesh, its edit, adjacency, unknowns and operator.
// Members are heap-held and never move: EnergyOperator keeps references to Vn and adj.
struct Problem {
  Mesh mesh;
  Points Vn;
  Adjacency adj;
  Unknowns unk;
  std::unique_ptr<EnergyOperator> op;
};

struct Case {
  std::string tier, mesh_path, system, build;
};

std::map<std::string, std::unique_ptr<Problem>>& problems() {
  static std::map<std::string, std::unique_ptr<Problem>> p;
  return p;
}

const Problem& problem(const Case& c) {
  auto& cache = problems();
  const std::string key = c.tier + "/" + c.system;
  auto it = cache.find(key);
  if (it != cache.end()) return *it->second;
  auto p = std::make_unique<Problem>();
  p->mesh = read_mesh(c.mesh_path);
  validate_mesh(p->mesh, Manifold::Allowed);  // LAP and TF (uniform) live on the vertex graph
  const Edit edit = harness::make_thesis_edit(p->mesh);
  p->Vn = Normalization::fit(p->mesh.V).apply(p->mesh.V);
  p->adj = vertex_adjacency(p->mesh);
  const auto kinds = classify(edit, ConstraintMode::Soft);
  check_every_component_anchored(p->adj, kinds);
  p->unk = make_unknowns(kinds, 1.0);
  p->op = std::make_unique<EnergyOperator>(p->Vn, p->mesh.F, p->adj, parse_enum<EnergyKind>(c.system), EnergyOptions{});
  return *cache.emplace(key, std::move(p)).first->second;
}

// Systems per (tier, system, build), built once.
const NormalSystem& system_of(const Case& c) {
  static std::map<std::string, std::unique_ptr<NormalSystem>> cache;
  const std::string key = c.tier + "/" + c.system + "/" + c.build;
  auto it = cache.find(key);
  if (it != cache.end()) return *it->second;
  const Problem& p = problem(c);
  auto s = std::make_unique<NormalSystem>(build_normal_system(*p.op, p.unk, parse_enum<Build>(c.build)));
  return *cache.emplace(key, std::move(s)).first->second;
}

// The deformation's right-hand side is not needed for timing a solve: any dense block of the right shape is.
DenseMat rhs_of(const NormalSystem& s) {
  DenseMat b = s.g0;
  b.array() += 1.0;  // g0 of TF is zero; keep the solve away from the trivial x = 0
  return b;
}

// Factorized solvers for the solve benchmarks, one per benchmark name, kept for the whole run: repetitions may be
// interleaved (--benchmark_enable_random_interleaving, as `./run track bench` runs them), and a solve must
// never pay for a factorization. The default suite holds about 0.7 GB of factors at its peak.
std::map<std::string, std::unique_ptr<LinearSolver>>& factored() {
  static std::map<std::string, std::unique_ptr<LinearSolver>> f;
  return f;
}

void set_counters(benchmark::State& st, const NormalSystem& s, const FactorStats* f, double bytes) {
  st.counters["n"] = benchmark::Counter(double(s.n()));
  st.counters["nnz"] = benchmark::Counter(double(s.build == Build::Dense ? s.K_dense.size() : s.K.nonZeros()));
  if (f) st.counters["nnz_L"] = benchmark::Counter(double(f->nnz_factor));
  st.counters["bytes"] = benchmark::Counter(bytes, benchmark::Counter::kDefaults, benchmark::Counter::kIs1024);
}

void bm_build(benchmark::State& st, Case c) {
  try {
    const Problem& p = problem(c);
    std::optional<NormalSystem> s;
    for (auto _ : st) {
      st.PauseTiming();
      s.reset();  // freeing the previous iteration's matrices is not the build
      st.ResumeTiming();
      s.emplace(build_normal_system(*p.op, p.unk, parse_enum<Build>(c.build)));
    }
    const double held = s ? double(s->total_held_bytes()) : 0.0;
    s.reset();
    set_counters(st, system_of(c), nullptr, held);
  } catch (const std::exception& e) {
    st.SkipWithError(e.what());
  }
}

void bm_analyze(benchmark::State& st, Case c, std::string backend) {
  try {
    const NormalSystem& s = system_of(c);
    SolverOptions so;
    so.block_size = s.block;
    std::unique_ptr<LinearSolver> solver;
    for (auto _ : st) {
      st.PauseTiming();
      solver.reset();
      solver = make_solver(backend, so);  // a fresh solver each time: construction and teardown are not timed
      st.ResumeTiming();
      solver->analyze(s.K);
    }
    const FactorStats f = solver ? solver->stats() : FactorStats{};
    set_counters(st, s, &f, double(f.factor_bytes));
  } catch (const std::exception& e) {
    st.SkipWithError(e.what());
  }
}

void bm_factorize(benchmark::State& st, Case c, std::string backend) {
  try {
    const NormalSystem& s = system_of(c);
    SolverOptions so;
    so.block_size = s.block;
    auto solver = make_solver(backend, so);
    solver->analyze(s.K);
    for (auto _ : st) solver->factorize(s.K);
    const FactorStats f = solver->stats();
    set_counters(st, s, &f, double(f.factor_bytes));
  } catch (const std::exception& e) {
    st.SkipWithError(e.what());
  }
}

void bm_solve(benchmark::State& st, Case c, std::string backend, std::string name) {
  try {
    const NormalSystem& s = system_of(c);
    std::unique_ptr<LinearSolver>& solver = factored()[name];
    if (!solver) {
      SolverOptions so;
      so.block_size = s.block;
      auto fresh = make_solver(backend, so);
      fresh->analyze(s.K);
      fresh->factorize(s.K);
      solver = std::move(fresh);
    }
    const DenseMat b = rhs_of(s);
    DenseMat x;
    for (auto _ : st) {
      solver->solve(b, x);
      benchmark::DoNotOptimize(x.data());
    }
    const FactorStats f = solver->stats();
    set_counters(st, s, &f, double(f.factor_bytes));
  } catch (const std::exception& e) {
    st.SkipWithError(e.what());
  }
}

// Deformers (the thesis edit, soft constraints) for the handle-mode phases, one per (tier, system, build,
// backend), kept for the whole run like the factored solvers.
Deformer& deformer_of(const Case& c, const std::string& backend) {
  static std::map<std::string, std::unique_ptr<Deformer>> cache;
  const std::string key = c.tier + "/" + c.system + "/" + c.build + "/" + backend;
  auto it = cache.find(key);
  if (it != cache.end()) return *it->second;
  const Problem& p = problem(c);
  DeformOptions o;  // from keys, as the benchmark's name spells them (methods/deform_options.h)
  const std::vector<std::pair<std::string, std::string>> items = {
      {"method", c.system}, {"constraints", "soft"}, {"build", c.build}, {"backend", backend}, {"frame_mode", "handle"}};
  for (const auto& [key, value] : items) set_deform_option(o, key, value);
  return *cache.emplace(key, make_deformer(p.mesh, harness::make_thesis_edit(p.mesh), o)).first->second;
}

void bm_precompute(benchmark::State& st, Case c, std::string backend) {
  try {
    Deformer& d = deformer_of(c, backend);
    for (auto _ : st) d.precompute_handle_frames();
    st.counters["bytes"] = benchmark::Counter(double(d.response_bytes()), benchmark::Counter::kDefaults,
                                              benchmark::Counter::kIs1024);
  } catch (const std::exception& e) {
    st.SkipWithError(e.what());
  }
}

void bm_frame_handle(benchmark::State& st, Case c, std::string backend) {
  try {
    Deformer& d = deformer_of(c, backend);
    const Mat4 T = harness::make_thesis_edit(problem(c).mesh).transform;
    for (auto _ : st) {
      Points V = d.deform(T);
      benchmark::DoNotOptimize(V.data());
    }
    st.counters["bytes"] = benchmark::Counter(double(d.response_bytes()), benchmark::Counter::kDefaults,
                                              benchmark::Counter::kIs1024);
  } catch (const std::exception& e) {
    st.SkipWithError(e.what());
  }
}

struct Options {
  std::string data;
  std::vector<std::string> tiers = {"hand", "armadillo"}, systems = {"lap", "tf"}, builds = {"structured"},
                           backends = {"multifrontal", "cholmod_supernodal", "cholmod_simplicial_ldlt",
                                       "eigen_simplicial_llt", "umfpack"};
  double simplicial_max_n = 30000;
};

void define_options(CLI::App& app, Options& o) {
  const char* src = std::getenv("DEFORMBENCH_SOURCE_DIR");
  o.data = src ? (fs::path(src) / "data").string() : "data";
  app.add_option("--data", o.data, "data folder")->capture_default_str();
  const std::vector<std::string> tiers = {"hand", "man", "armadillo", "armadillo_loop1"};
  auto* t = app.add_option("--tiers", o.tiers, "meshes")->delimiter(',')->check(cli::OneOf(tiers));
  t->capture_default_str();
  app.add_flag("--full", "all four tiers (adds man and the 104k armadillo_loop1)")->excludes(t);
  app.add_option("--systems", o.systems, "systems")->delimiter(',')->check(cli::OneOf({"lap", "tf"}))
      ->capture_default_str();
  app.add_option("--builds", o.builds, "builds (naive and dense time their build too; dense: hand tier only)")
      ->delimiter(',')->check(cli::OneOf({"structured", "naive", "dense"}))->capture_default_str();
  app.add_option("--backends", o.backends, "backends")->delimiter(',')->check(cli::OneOf(solver_names()))
      ->capture_default_str();
  app.add_option("--simplicial-max-n", o.simplicial_max_n, "simplicial backends only up to this many unknowns")
      ->transform(cli::Integer(1, 1000000000))->capture_default_str();
  // Google Benchmark rejects flags it does not know, and we do not know its: they pass through to it.
  app.allow_extras();
  app.footer("Google Benchmark flags (--benchmark_filter=REGEX, --benchmark_repetitions=N, ...) pass through.");
}

std::string mesh_path(const std::string& data, const std::string& tier) {
  const fs::path d(data);
  if (tier == "armadillo_loop1") return (d / "generated" / "armadillo_loop1.off").string();
  if (tier == "hand" || tier == "man" || tier == "armadillo") return (d / "meshes" / (tier + ".off")).string();
  throw InputError(fmt::format("unknown tier '{}' (hand, man, armadillo, armadillo_loop1)", tier));
}

void register_all(const Options& o) {
  for (const auto& b : o.backends) solver_info(b);  // unknown names fail here, not mid-run
  for (const auto& tier : o.tiers) {
    const std::string path = mesh_path(o.data, tier);
    if (!fs::exists(path)) throw InputError(fmt::format("mesh {} not found: run scripts/data.sh", path));
    for (const auto& system : o.systems) {
      parse_enum<EnergyKind>(system);
      for (const auto& build : o.builds) {
        parse_enum<Build>(build);
        if (build == "dense" && tier != "hand") continue;  // gigabytes beyond the hand tier
        const Case c{tier, path, system, build};
        const std::string stem = fmt::format("mesh:{}/system:{}/build:{}", tier, system, build);
        benchmark::RegisterBenchmark(("build/" + stem).c_str(), bm_build, c)->Unit(benchmark::kMillisecond);
        if (build == "dense") continue;  // the sparse backends take K, not K_dense
        for (const auto& be : o.backends) {
          if (be.find("simplicial") != std::string::npos &&
              double(problem(c).mesh.num_vertices()) * (system == "lap" ? 1 : 3) > o.simplicial_max_n)
            continue;
          const std::string tail = stem + "/backend:" + be;
          benchmark::RegisterBenchmark(("analyze/" + tail).c_str(), bm_analyze, c, be)->Unit(benchmark::kMillisecond);
          benchmark::RegisterBenchmark(("factorize/" + tail).c_str(), bm_factorize, c, be)
              ->Unit(benchmark::kMillisecond);
          benchmark::RegisterBenchmark(("solve/" + tail).c_str(), bm_solve, c, be, "solve/" + tail)
              ->Unit(benchmark::kMicrosecond);
          benchmark::RegisterBenchmark(("precompute/" + tail).c_str(), bm_precompute, c, be)
              ->Unit(benchmark::kMillisecond);
        }
        // The frame streams the responses whichever backend solved for them.
        benchmark::RegisterBenchmark(("frame_handle/" + stem).c_str(), bm_frame_handle, c, o.backends.front())
            ->Unit(benchmark::kMicrosecond);
      }
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Google Benchmark suite of the build, analyze, factorize and solve phases", "bench_phases");
  Options o;
  define_options(app, o);
  return cli::run(app, argc, argv, [&] {
    if (app.count("--full") > 0) o.tiers = {"hand", "man", "armadillo", "armadillo_loop1"};
    register_all(o);
    std::vector<std::string> rest = app.remaining();  // Google Benchmark's flags, in order
    for (const std::string& r : rest)
      if (r.rfind("--benchmark_", 0) != 0)
        throw UsageError(fmt::format("unknown option '{}' (bench_phases --help; Google Benchmark's flags start "
                                     "with --benchmark_)", r));
    std::vector<char*> args{argv[0]};
    for (std::string& r : rest) args.push_back(r.data());
    int n = static_cast<int>(args.size());
    benchmark::Initialize(&n, args.data());
    if (benchmark::ReportUnrecognizedArguments(n, args.data())) return 1;
    for (const auto& [k, v] : provenance().columns()) benchmark::AddCustomContext("deformbench_" + k, v);
    // The suite's definition: bump it when a benchmark's work or a counter's meaning changes, so that the gate
    // refuses a baseline of the old definition as stale (python/dbtools/track/provenance.py).
    benchmark::AddCustomContext("deformbench_suite_version", "1");
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
  });
}
