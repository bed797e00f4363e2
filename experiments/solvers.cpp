// Solver choice: which linear solver backend and fill-reducing ordering to use for the LAP and TF normal
// equations, and the thesis' claim (section 2.2.3) that Cholesky is slightly faster than LU and Bunch-Kaufman
// LDL^T; least squares on A itself (SPQR, A^T A never formed) as the alternative to normal equations.
//
// Grid: the tiers of a config (data/experiments/solvers.toml) x systems (lap, tf) x backends (every backend of the
// registry and spqr) x orderings (every one a backend accepts, plus "vertex-metis", see harness/solver_cell.h) x
// thread counts (--threads; each cell's OpenMP, BLAS and own threads set per backend by harness/thread_policy.h,
// speedup and parallel_efficiency against the smallest count). Instead of the tiers, --edit runs an edit's systems
// (any .edit or BS08 stem, lap / tf / lri with deform's method, constraint and weight options) and --matrix any
// SPD system of a Matrix Market file (checked before any cell).
// Every cell (harness/solver_cell.h) runs in a fresh child process, so peak RSS and timings are per cell; a
// failing or crashing backend is a row with its status, never a dead driver. Orderings that fill in badly run only
// up to --poor-ordering-max-n unknowns: "natural" (the file's vertex order) for every sparse direct backend, and
// "amd" for Eigen's SparseLU (a symmetric ordering for a column-pivoting LU, far slower and larger than its default
// COLAMD). error_vs_cholmod compares each cell's deformed positions with those of the CHOLMOD
// supernodal / default-ordering cell of the same tier and system, after the cells have run.
//
// Writes --out (default RESULTS/solvers.csv, --results required, long: one row per cell x measure; the provenance columns record the
// BLAS core of this run). results/solvers.md is the report step's (python/dbtools/). Options: --help.
// Exits with kCellsFailedExit (harness/driver.h) when a cell failed, after writing every row.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include <fmt/format.h>

#include "core/cli.h"
#include "core/csv.h"
#include "solvers/base/error.h"
#include "core/provenance.h"
#include "core/spread.h"
#include "harness/driver.h"
#include "harness/mesh_source.h"
#include "harness/positions.h"
#include "harness/runner.h"
#include "harness/shards.h"
#include "harness/solver_cell.h"
#include "harness/subprocess.h"
#include "harness/thread_policy.h"
#include "edit/edit_io.h"
#include "methods/deform_option_flags.h"
#include "methods/edit_system.h"
#include "systems/matrix_market.h"
#include "mesh/mesh_io.h"
#include "solvers/linear_solver.h"

namespace fs = std::filesystem;
using namespace db;
using namespace db::harness;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kMiB = 1024.0 * 1024.0;
const char* const kReferenceBackend = "cholmod_supernodal";
const char* const kVertexOrdering = "vertex-metis";

bool contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

// ------------------------------------------------------------------------------------------------ options
struct Options {
  std::string data = "data", results, out, cache, factor_dir, edit;
  std::vector<std::string> matrix;  // A.mtx[,B.mtx]
  int matrix_block = 1;
  DeformOptionValues edit_values;   // --edit's method, constraint and weight options
  DeformOptions edit_options;
  bool full = false, dry_run = false;
  std::vector<std::string> tiers, full_tiers, meshes, only, systems = {"lap", "tf"}, backends, orderings;
  double dense_max_n = 4000, poor_ordering_max_n = 20000, iterative_max_n = 20000, cell_timeout_s = 300,
         cell_memory_mb = 6144;
  std::vector<int> threads = {1};
  int solve_reps = 10, factor_reps = 5;
  double rep_seconds = 2.0;
  unsigned seed = 1;
  ShardOptions shards;
};

void define_options(CLI::App& app, Options& o) {
  std::vector<std::string> backends = solver_names();
  backends.push_back(kLeastSquaresBackend);
  add_config_option(app, "data/experiments/solvers.toml");
  app.add_option("--data", o.data, "data directory; relative mesh paths of --tier are inside it")->capture_default_str();
  app.add_option("--results", o.results, "where solvers.csv and the cells' scratch files go (required: the study "
                 "writes into the repository's results/ only when asked)");
  app.add_option("--out", o.out, "the CSV (default RESULTS/solvers.csv)");
  app.add_option("--tier", o.tiers, "a tier: NAME=MESH[+loopK] (MESH relative to --data)")->delimiter(',');
  app.add_option("--full-tier", o.full_tiers, "tiers --full adds (same form)")->delimiter(',');
  app.add_option("--mesh", o.meshes, "another tier, NAME=PATH[+loopK] (PATH as given): your own mesh");
  app.add_option("--only", o.only, "run only these tiers (labels, comma-separated)")->delimiter(',');
  app.add_flag("--full", o.full, "add --full-tier");
  app.add_flag("--dry-run", o.dry_run, "print the grid's cells (one spec a line) and exit");
  app.add_option("--systems", o.systems, "systems")->delimiter(',')->check(cli::OneOf({"lap", "tf"}))->capture_default_str();
  app.add_option("--backends", o.backends, "backends (default: every backend and spqr)")->delimiter(',')
      ->check(cli::OneOf(backends).description(""));
  app.add_option("--orderings", o.orderings, "keep only these orderings (default: every one a backend accepts)")
      ->delimiter(',');
  app.add_option("--dense-max-n", o.dense_max_n, "dense backends up to this many unknowns")->check(cli::Real(0, 1e9))
      ->capture_default_str();
  app.add_option("--poor-ordering-max-n", o.poor_ordering_max_n, "orderings that fill in badly up to this n")
      ->check(cli::Real(0, 1e9))->capture_default_str();
  app.add_option("--iterative-max-n", o.iterative_max_n, "iterative backends up to this n")->check(cli::Real(0, 1e9))
      ->capture_default_str();
  app.add_option("--threads", o.threads, "thread counts: every cell runs at each (harness/thread_policy.h sets "
                 "OpenMP, BLAS and assembly threads per backend; 0: as the environment says)")
      ->delimiter(',')->transform(cli::Integer(0, 4096))->capture_default_str();
  app.add_option("--edit", o.edit, "the study on this edit's systems instead of the tiers: a .edit file or a BS08 "
                 "stem, with the method, constraint and weight options below (deformbench deform's)")
      ->type_name("EDIT");
  app.add_option("--matrix", o.matrix, "the study on this SPD system instead of the tiers: A.mtx[,B.mtx] (Matrix "
                 "Market; B: right-hand sides, else a synthetic one)")
      ->delimiter(',')->type_name("A.mtx[,B.mtx]")->expected(1, 2)->excludes("--edit");
  app.add_option("--matrix-block", o.matrix_block, "--matrix: unknowns per vertex block, what the backends compress "
                 "their graph by (3 for a tf system; `deformbench export-system` prints it)")
      ->transform(cli::Integer(1, 64))->capture_default_str();
  add_deform_option_flags(app, o.edit_values, system_option_groups());
  app.add_option("--cell-timeout-s", o.cell_timeout_s, "kill a cell after this")->check(cli::Real(1, 1e7))->capture_default_str();
  app.add_option("--cell-memory-mb", o.cell_memory_mb, "a cell's address-space limit")->check(cli::Real(64, 1e9))
      ->capture_default_str();
  app.add_option("--solve-reps", o.solve_reps, "solves per cell, at most")->transform(cli::Integer(1, 100000))->capture_default_str();
  app.add_option("--factor-reps", o.factor_reps, "factorizations per cell, at most")->transform(cli::Integer(1, 100000))
      ->capture_default_str();
  app.add_option("--rep-seconds", o.rep_seconds, "stop repeating a phase after this long")->check(cli::Real(0, 1e6))
      ->capture_default_str();
  app.add_option("--seed", o.seed, "seed of the synthetic right-hand side")->transform(cli::Integer(0, 4294967295LL))
      ->capture_default_str();
  app.add_option("--factor-dir", o.factor_dir, "out of core: backends that can keep their factor in scratch files here")
      ->check(CLI::ExistingDirectory);
  app.add_option("--mesh-cache", o.cache, "where generated Loop levels go (default RESULTS/cells/meshes)");
  add_shard_options(app, o.shards);
}

// --edit's options (checked together) and the other sources' files, before any work: a bad edit or matrix is one
// clear error (exit 2), not a failed cell per backend.
void check_sources(const CLI::App& app, Options& o) {
  const std::vector<std::string> given = deform_option_keys_given(app, o.edit_values);
  if (!given.empty() && o.edit.empty())
    throw UsageError(deform_option_def(given.front()).flag + ": the method, constraint and weight options go with --edit");
  if (app.count("--matrix-block") > 0 && o.matrix.empty()) throw UsageError("--matrix-block goes with --matrix");
  if (!o.edit.empty()) {
    o.edit_options = deform_options_given(app, o.edit_values);
    load_edit_case(o.edit);
  }
  if (!o.matrix.empty()) {
    const SpMat K = read_market_spd(o.matrix[0]);
    if (o.matrix.size() > 1) read_market_array(o.matrix[1], K.rows());
    if (K.rows() % o.matrix_block != 0)
      throw UsageError(fmt::format("--matrix-block {}: the matrix's {} rows are not whole blocks", o.matrix_block,
                                   K.rows()));
  }
}

void finish_options(const CLI::App& app, Options& o) {
  if (o.results.empty() && !o.dry_run)
    throw UsageError("--results DIR is required: where solvers.csv and the cells' scratch files go (`./run "
                     "reproduce` passes the repository's results/)");
  if (o.results.empty()) o.results = ".";
  check_output_dir("--results", o.results);
  if (o.out.empty()) o.out = (fs::path(o.results) / "solvers.csv").string();
  else cli::check_output("--out", o.out, {".csv"});
  if (o.cache.empty()) o.cache = (fs::path(o.results) / "cells" / "meshes").string();
  check_output_dir("--mesh-cache", o.cache);
  if (o.backends.empty()) {
    o.backends = solver_names();
    o.backends.push_back(kLeastSquaresBackend);
  }
  // The reference runs first: its positions are what every other cell is compared with.
  if (auto it = std::find(o.backends.begin(), o.backends.end(), kReferenceBackend); it != o.backends.end())
    std::rotate(o.backends.begin(), it, it + 1);
  check_sources(app, o);
}

// The label of a file's rows: its name without the extension (a BS08 stem: its last part).
std::string label_of(const std::string& path) { return fs::path(path).stem().string(); }

std::vector<MeshSource> tier_sources(const Options& o) {
  if (!o.edit.empty()) return {{label_of(o.edit), o.edit, 0, ""}};
  if (!o.matrix.empty()) return {{label_of(o.matrix[0]), o.matrix[0], 0, ""}};
  std::vector<MeshSource> all;
  for (const auto& t : o.tiers) all.push_back(parse_mesh_source(t, o.data));
  if (o.full)
    for (const auto& t : o.full_tiers) all.push_back(parse_mesh_source(t, o.data));
  for (const auto& m : o.meshes) all.push_back(parse_mesh_source(m, ""));
  if (all.empty()) throw UsageError("no tier: give --tier or --mesh (or a --config that lists them)");
  return select_sources(all, o.only);
}

// Pins the thread counts of this run by re-executing the driver with OMP_NUM_THREADS, OPENBLAS_NUM_THREADS and
// DEFORMBENCH_THREADS set: the libraries read them when they load, and the provenance columns then record what the
// driver used (each cell's own, set per backend by harness/thread_policy.h, are its threads and thread_env
// columns). Why 1 by default: on a shared 2-core machine a parallel region waits for a descheduled thread (CG
// ran orders of magnitude slower with 2 threads than with 1), and one thread compares algorithms, not schedulers.
void pin_threads(const std::vector<int>& counts, char** argv) {
  if (counts.size() != 1 || counts[0] <= 0) return;  // several: each cell's are set when it starts
  const int threads = counts[0];
  const std::string want = std::to_string(threads);
  auto is = [&](const char* k) {
    const char* v = std::getenv(k);
    return v && want == v;
  };
  if (is("OMP_NUM_THREADS") && is("OPENBLAS_NUM_THREADS") && is("DEFORMBENCH_THREADS")) return;
  for (const char* k : {"OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "DEFORMBENCH_THREADS"}) ::setenv(k, want.c_str(), 1);
  const std::string exe = self_executable();
  ::execv(exe.c_str(), argv);
  throw Error("could not re-execute " + exe + " with the thread settings");
}

// ------------------------------------------------------------------------------------------------ the grid
struct Record {
  SolverCell cell;
  std::string family;
  double vertices = kNaN, n = kNaN;
  CellResult res;
};

// Orderings of one backend in the grid.
std::vector<std::string> orderings_for(const Options& o, const std::string& backend) {
  const std::string family = solver_family(backend);
  std::vector<std::string> v = solver_orderings(backend);
  const bool sparse_direct = family == "sparse-cholesky" || family == "sparse-lu";
  if (sparse_direct && contains(v, "natural") && o.edit.empty() && o.matrix.empty()) v.push_back(kVertexOrdering);
  if (!sparse_direct) v = {"default"};  // dense and iterative: nothing to order; spqr: its own choice
  // The refined backends factor as multifrontal or mumps does (their orderings' rows say what they cost); their rows
  // are about precision: the default ordering only.
  if (backend == "multifrontal_mixed" || backend == "multifrontal_refined" || backend == "mumps_refined")
    v = {"default"};
  if (o.orderings.empty()) return v;
  std::vector<std::string> keep;
  for (const auto& x : v)
    if (contains(o.orderings, x)) keep.push_back(x);
  return keep;
}

// Why a cell of the grid is not run ("" = it runs); `default_used` is what "default" resolved to for the backend.
std::string skip_reason(const Options& o, const Record& r, const std::string& default_used) {
  const std::string& ord = r.cell.ordering;
  const bool sparse_direct = r.family == "sparse-cholesky" || r.family == "sparse-lu" || r.family == "least-squares";
  if (ord != "default" && ord == default_used)
    return fmt::format("skipped: same as the default ordering ({}), measured in that row", ord);
  if (r.family == "dense" && r.n > o.dense_max_n)
    return fmt::format("skipped: dense over limit (n = {:.0f} > --dense-max-n {:.0f})", r.n, o.dense_max_n);
  if (r.family == "iterative" && r.n > o.iterative_max_n)
    return fmt::format("skipped: iterative over limit (n = {:.0f} > --iterative-max-n {:.0f}; CG iterations grow ~n "
                       "here)",
                       r.n, o.iterative_max_n);
  if (sparse_direct && (ord == "natural" || (r.cell.backend == "eigen_sparse_lu" && ord == "amd")) &&
      r.n > o.poor_ordering_max_n)
    return fmt::format("skipped: {} ordering fills in badly for {} (n = {:.0f} > --poor-ordering-max-n {:.0f})", ord,
                       r.cell.backend, r.n, o.poor_ordering_max_n);
  return "";
}

void log_record(const Record& r) {
  const CellResult& c = r.res;
  if (c.ok())
    std::cerr << fmt::format(
        "[solvers] {:52s} n={:7.0f} analyze {:8.4f} s  factorize {:8.4f} s  solve {:9.5f} s  nnzL {:10.0f}  "
        "{:6.2f} GF/s  peak {:7.1f} MiB  res {:.1e}  err {:.1e}\n",
        r.cell.key(), c.get("n"), c.get("analyze_s"), c.get("factorize_s"), c.get("solve_s"), c.get("nnz_factor"),
        c.get("gflops"), c.get("peak_rss_bytes") / kMiB, c.get("residual"), c.get("error_exact"));
  else
    std::cerr << fmt::format("[solvers] {:52s} {}\n", r.cell.key(),
                             c.message.rfind(c.status, 0) == 0 ? c.message : c.status + ": " + c.message);
}

// error_vs_double of the refined cells (multifrontal_mixed, multifrontal_refined, mumps_refined): the largest
// coordinate difference from the double multifrontal cell's positions (default ordering), which are normalized:
// units of the bounding-box diagonal; error_vs_refined of every other cell: the same from the multifrontal_refined
// cell's, the exact solution to the tolerance (of the mixed cell, what the float factor leaves; of a direct one, its
// own rounding's effect on this ill-conditioned system).
void compare_with_double(std::vector<Record>& group) {
  auto find = [&group](const char* backend) {
    return std::find_if(group.begin(), group.end(), [backend](const Record& r) {
      return r.cell.backend == backend && r.cell.ordering == "default" && r.res.ok() && fs::exists(r.cell.positions);
    });
  };
  const auto dbl = find("multifrontal"), ref = find("multifrontal_refined");
  auto apart = [](const Record& a, const Record& b) {
    return (read_positions(a.cell.positions) - read_positions(b.cell.positions)).cwiseAbs().maxCoeff();
  };
  if (dbl != group.end())
    for (auto r : {ref, find("multifrontal_mixed"), find("mumps_refined")})
      if (r != group.end()) r->res.set("error_vs_double", apart(*r, *dbl), "diagonal");
  if (ref == group.end()) return;
  for (Record& r : group)
    if (&r != &*ref && r.res.ok() && fs::exists(r.cell.positions))
      r.res.set("error_vs_refined", apart(r, *ref), "diagonal");
}

// error_vs_cholmod of every cell of one tier and system that left positions, against the reference's.
void compare_with_reference(std::vector<Record>& group) {
  compare_with_double(group);
  auto ref = std::find_if(group.begin(), group.end(), [](const Record& r) {
    return r.cell.backend == kReferenceBackend && r.cell.ordering == "default" && r.res.ok();
  });
  if (ref != group.end()) {
    const Points R = read_positions(ref->cell.positions);
    for (Record& r : group)
      if (r.res.ok() && fs::exists(r.cell.positions))
        r.res.set("error_vs_cholmod", (read_positions(r.cell.positions) - R).norm() / R.norm(), "relative");
  }
  for (const Record& r : group) fs::remove(r.cell.positions);
}

// One cell of the grid: its tier (resolved when it runs) and the cell.
struct Planned {
  MeshSource tier;
  SolverCell cell;
};

// The systems of the grid: --systems for the tiers, the method's for --edit, "matrix" for --matrix.
std::vector<std::string> systems_of(const Options& o) {
  if (!o.matrix.empty()) return {"matrix"};
  if (o.edit.empty()) return o.systems;
  if (o.edit_options.method == Method::Lri) return {"lri-frames", "lri-positions"};
  return {to_string(o.edit_options.method)};
}

// The cell of one tier, system, backend and ordering.
SolverCell cell_for(const Options& o, const MeshSource& t, const std::string& system, const std::string& backend,
                    const std::string& ordering) {
  SolverCell c;
  c.model = t.label;
  c.mesh = t.levels ? fmt::format("{}+loop{}", t.path, t.levels) : t.path;
  c.system = system;
  c.backend = backend;
  c.ordering = ordering;
  c.solve_reps = o.solve_reps;
  c.factor_reps = o.factor_reps;
  c.rep_seconds = o.rep_seconds;
  c.seed = o.seed;
  if (backend != kLeastSquaresBackend && solver_info(backend).out_of_core) c.factor_dir = o.factor_dir;
  if (!o.edit.empty()) c.source = "edit", c.options = option_items_text(o.edit_options);
  if (!o.matrix.empty()) c.source = "matrix", c.rhs = o.matrix.size() > 1 ? o.matrix[1] : "", c.block = o.matrix_block;
  return c;
}

//! The grid, a plain list: tiers x systems x backends x orderings x thread counts (the reference backend first in
//! each group).
std::vector<Planned> plan(const Options& o) {
  std::vector<Planned> g;
  for (const MeshSource& t : tier_sources(o))
    for (const auto& system : systems_of(o))
      for (const auto& backend : o.backends)
        for (const auto& ordering : orderings_for(o, backend))
          for (int threads : o.threads) {
            SolverCell c = cell_for(o, t, system, backend, ordering);
            c.threads = threads;
            g.push_back({t, c});
          }
  return g;
}

// The tier's mesh file and vertex count, or why there is none.
struct Tier {
  std::string path, error;
  double vertices = kNaN;
};

Tier load_tier(const Options& o, const MeshSource& t) {
  Tier r;
  r.path = t.path;
  if (!o.matrix.empty()) return r;  // checked in check_sources; n comes from its cells
  if (!o.edit.empty()) {
    r.vertices = load_edit_case(t.path).mesh.num_vertices();
    return r;
  }
  try {
    r.path = resolve_mesh(t, (fs::path(o.data) / "generated").string(), o.cache, self_executable());
    r.vertices = read_mesh(r.path).num_vertices();
  } catch (const std::exception& e) {
    r.error = e.what();
  }
  return r;
}

// Runs one cell of the grid; `default_used` is what "default" resolved to for its backend (from that cell).
Record run_planned(const Options& o, const Planned& p, const Tier& tier, std::string& default_used) {
  const int block = p.cell.system == "lap" || p.cell.system == "lri-positions" ? 1 : 3;
  Record r{p.cell, solver_family(p.cell.backend), tier.vertices, tier.vertices * block, {}};
  r.cell.mesh = tier.path;
  r.cell.positions = (fs::path(o.results) / "cells" / "solvers" /
                      fmt::format("{}_{}__{}_{}_t{}.pos", r.cell.model, r.cell.system, r.cell.backend, r.cell.ordering,
                                  r.cell.threads))
                         .string();
  std::string skip = tier.error.empty() ? skip_reason(o, r, default_used) : "";
  if (skip.empty() && !r.cell.source.empty() && r.cell.backend == kLeastSquaresBackend)
    skip = "skipped: least squares (spqr) needs A itself: the tiers' cells only (`deformbench export-system "
           "--least-squares` writes an edit's A)";
  if (r.cell.threads > 0) export_thread_settings(thread_settings(r.cell.backend, r.cell.threads));
  RunOptions ro;
  ro.timeout_s = o.cell_timeout_s;
  ro.address_space_bytes = static_cast<std::size_t>(o.cell_memory_mb * kMiB);
  if (!tier.error.empty()) r.res = CellResult::with_status("error", tier.error);
  else if (!skip.empty()) r.res = CellResult::with_status("skipped", skip);
  else r.res = run_cell(self_executable(), r.cell.to_spec(), ro);
  if (r.cell.ordering == "default" && r.res.ok()) default_used = r.res.text("ordering_used");
  log_record(r);
  return r;
}

std::vector<Record> run_grid(const Options& o, const std::vector<Planned>& grid) {
  std::vector<Record> recs, group;
  fs::create_directories(fs::path(o.results) / "cells" / "solvers");
  Tier tier;
  std::string default_used;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const Planned& p = grid[i];
    if (i == 0 || p.cell.mesh != grid[i - 1].cell.mesh) tier = load_tier(o, p.tier);
    if (i == 0 || p.cell.backend != grid[i - 1].cell.backend) default_used.clear();
    group.push_back(run_planned(o, p, tier, default_used));
    const bool last = i + 1 == grid.size() || grid[i + 1].cell.mesh != p.cell.mesh ||
                      grid[i + 1].cell.system != p.cell.system;
    if (!last) continue;
    compare_with_reference(group);  // the tier and system are done
    for (Record& r : group) recs.push_back(std::move(r));
    group.clear();
  }
  return recs;
}

// speedup and parallel_efficiency of every cell run at several thread counts: its factorize time (the fastest
// repetition) against the same cell's at the smallest count, efficiency = speedup * smallest / threads.
void add_parallel_efficiency(std::vector<Record>& recs) {
  auto same = [](const SolverCell& a, const SolverCell& b) {
    return a.model == b.model && a.system == b.system && a.backend == b.backend && a.ordering == b.ordering;
  };
  for (Record& r : recs) {
    if (!r.res.ok() || r.cell.threads <= 0) continue;
    const Record* base = nullptr;
    for (const Record& b : recs)
      if (same(b.cell, r.cell) && b.res.ok() && b.cell.threads > 0 && (!base || b.cell.threads < base->cell.threads))
        base = &b;
    const double t0 = base ? base->res.get(spread_name("factorize_s", "min")) : kNaN,
                 t = r.res.get(spread_name("factorize_s", "min"));
    if (!base || base == &r || !(t0 > 0) || !(t > 0)) continue;
    r.res.set("speedup", t0 / t, "ratio");
    r.res.set("parallel_efficiency", t0 / t * base->cell.threads / r.cell.threads, "ratio");
  }
}

// ------------------------------------------------------------------------------------------------ CSV
// The schema of solvers.csv: Always rows for every cell (empty where not measured), the others where measured.
const std::vector<MeasureDef>& solver_measures() {
  const Keep A = Keep::Always, M = Keep::IfMeasured;
  static const std::vector<MeasureDef> d = {
      {"vertices", "count", A},          {"n", "count", A},
      {"nnz", "count", M},               {"rhs_cols", "count", M},
      {"build_s", "s", M},               {"order_s", "s", M},
      {"analyze_s", "s", A},             {"factorize_s", "s", A},  // each timing with its spread (cell.h)
      {"solve_s", "s", A},               {"nnz_factor", "count", A},
      {"build_cpu_s", "s", M},           {"analyze_cpu_s", "s", M},
      {"factorize_cpu_s", "s", M},       {"solve_cpu_s", "s", M},
      {"factor_flops", "flop", M},       {"gflops", "GFlop/s", M},
      {"matrix_bytes", "bytes", M},      {"factor_bytes", "bytes", A},
      {"baseline_rss_bytes", "bytes", M}, {"peak_rss_bytes", "bytes", A},
      {"ru_maxrss_bytes", "bytes", M},   {"iterations", "count", M},
      {"residual", "relative", A},       {"residual_synthetic", "relative", M},
      {"error_exact", "relative", A},    {"error_vs_cholmod", "relative", M},
      {"error_vs_double", "diagonal", M}, {"error_vs_refined", "diagonal", M},
      {"cell_wall_s", "s", M},           {"load_avg_1m", "count", M},
      {"speedup", "ratio", M},           {"parallel_efficiency", "ratio", M},  // --threads with several counts
      {"blas_threads_used", "count", M}, {"omp_threads_used", "count", M},
      {"own_threads_used", "count", M},
  };
  return d;
}

void write_csv(const std::string& path, std::vector<Record> recs) {
  CsvTable csv;
  for (Record& r : recs) {
    if (!r.res.has("vertices")) r.res.set("vertices", r.vertices);
    if (!r.res.has("n")) r.res.set("n", r.n);
    add_measure_rows(csv,
                     {{"model", r.cell.model},
                      {"vertices", std::isnan(r.vertices) ? "" : num(r.vertices)},
                      {"system", r.cell.system},
                      {"backend", r.cell.backend},
                      {"family", r.family},
                      {"ordering", r.cell.ordering},
                      {"ordering_used", r.res.text("ordering_used")},
                      {"threads", r.cell.threads > 0 ? std::to_string(r.cell.threads) : ""},
                      {"thread_env", r.cell.threads > 0 ? thread_settings(r.cell.backend, r.cell.threads).text() : ""}},
                     r.res, solver_measures());
  }
  if (!csv.empty()) csv.write(path);
}

// A cell's group: its tier and system (they share the loaded mesh and the reference cell).
std::string group_of(const Planned& p) { return p.tier.label + "|" + p.cell.system; }

// --merge-shards N: the shards' solvers.csv into --out, every group's rows in grid order.
int merge_shards(const Options& o, const std::vector<Planned>& grid) {
  std::vector<std::string> order;
  for (const Planned& p : grid)
    if (order.empty() || order.back() != group_of(p)) order.push_back(group_of(p));
  merge_shard_csv(o.results, o.shards.merge, fs::path(o.out).filename().string(), o.out, order,
                  [](const CsvRow& r) { return r.at("model") + "|" + r.at("system"); });
  std::cerr << fmt::format("[solvers] merged {} shards into {}\n", o.shards.merge, o.out);
  return 0;
}

// --shard I/N: the shard's cells of the grid; its CSV and scratch files go to RESULTS/shards/I-of-N/.
std::vector<Planned> shard_of(Options& o, const std::vector<Planned>& grid) {
  const Shard s = o.shards.parsed();
  if (!s.active()) return grid;
  o.results = shard_directory(o.results, s.index, s.count);
  o.out = (fs::path(o.results) / fs::path(o.out).filename()).string();
  return shard_slice(grid, s, group_of);
}

int run(const CLI::App& app, Options& o, char** argv) {
  finish_options(app, o);
  const std::vector<Planned> all = plan(o);  // the tiers are checked before any work
  if (o.shards.merge > 0) return merge_shards(o, all);
  const std::vector<Planned> grid = shard_of(o, all);
  if (o.dry_run) {
    for (const Planned& p : grid) std::cout << p.cell.to_spec().text() << "\n";
    return 0;
  }
  pin_threads(o.threads, argv);
  fs::create_directories(o.results);
  std::cerr << "[solvers] " << provenance_summary() << "\n";
  std::vector<Record> recs = run_grid(o, grid);
  add_parallel_efficiency(recs);
  write_csv(o.out, recs);
  std::cerr << "[solvers] wrote " << o.out << "\n";
  FailedCells failed("solvers");
  for (const Record& r : recs) failed.note(r.cell.to_spec().text(), r.res);
  return failed.exit_code();
}

}  // namespace

int main(int argc, char** argv) {
  if (is_cell_invocation(argc, argv)) return cell_main(argc, argv, {solver_kind(), loop_subdivide_kind()});
  CLI::App app("Solver choice for the LAP and TF systems: backends x orderings x tiers, each cell in a fresh child "
               "process; least squares on A (SPQR) beside the normal equations.",
               "exp_solvers");
  Options o;
  define_options(app, o);
  return cli::run(app, argc, argv, [&] { return run(app, o, argv); });
}
