// Solver choice (issue 4): which linear solver backend and fill-reducing ordering to use for the LAP and TF
// normal equations, and the thesis' claim (section 2.2.3) that Cholesky is slightly faster than LU and
// Bunch-Kaufman LDL^T.
//
// Grid: tiers (hand, man, armadillo; --full adds armadillo_loop1) x systems (lap, tf) x backends x orderings.
// The system of every tier is the thesis edit (harness/thesis_edit.h: whole-mesh ROI, 100 handle vertices at one
// extreme, 100 anchors at the other) with SOFT constraints, so K is #V x #V (lap) or 3#V x 3#V (tf), built with
// the structured build. Every cell runs in a fresh child process (this executable re-run with --cell), so peak
// RSS and timings are per cell; a failing or crashing backend is a row with its status, never a dead driver.
//
// Right-hand sides, per cell: the deformation's own (g0 + w^2 * soft targets, the full drag of the handle) and a
// synthetic one b = K x_ref for a seeded random x_ref, whose exact solution is known. Errors reported:
//   residual            ||K x - b|| / ||b|| of the deformation RHS
//   residual_synthetic  the same for b = K x_ref
//   error_exact         ||x - x_ref|| / ||x_ref||
//   error_vs_cholmod    ||X - X_cholmod|| / ||X_cholmod|| of the deformed (normalized) positions against the
//                       CHOLMOD supernodal / default-ordering cell of the same tier and system (the reference)
//
// Orderings: every value the backend accepts (solver_info().orderings), plus "vertex-metis": the deformer's own
// path, the unknowns renumbered by METIS on the vertex graph before assembly and the solver run with the natural
// ordering (its cost is reported as order_s and counted into analyze_s). Orderings that fill in badly run only up
// to --poor-ordering-max-n unknowns: "natural" (the file's vertex order) for every sparse direct backend, and
// "amd" for Eigen's SparseLU (a symmetric ordering for a column-pivoting LU: 123 s and 2 GB on man tf, where
// its default COLAMD takes 15 s).
//
//   exp_solvers --data DIR --results DIR [--full] [--tiers hand,man,...] [--systems lap,tf]
//               [--backends a,b,...] [--orderings a,b,...] [--dense-max-n N] [--poor-ordering-max-n N]
//               [--iterative-max-n N] [--threads N (default 1; 0 = as the environment says)]
//               [--cell-timeout-s S] [--cell-memory-mb MB] [--solve-reps N] [--factor-reps N]
//               [--rep-seconds S] [--seed N]
//               [--out FILE] [--md FILE] [--no-md] [--blas-compare FILE,...] [--summarize]
//
// --summarize: no measurement; rewrites the Markdown from the CSV given by --out (default RESULTS/solvers.csv)
// and the --blas-compare CSVs (e.g. after editing the summary code).
//
// Writes RESULTS/solvers.csv (long: one row per cell x measure; provenance columns record the BLAS core of this
// run) and RESULTS/solvers.md (the verdict). --blas-compare reads CSVs of the same driver run under another
// OPENBLAS_CORETYPE (scripts/experiments.sh makes them) and adds their factorize / solve ratios to the summary.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <random>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "core/args.h"
#include "core/atomic_file.h"
#include "core/csv.h"
#include "core/error.h"
#include "core/provenance.h"
#include "core/resources.h"
#include "core/timer.h"
#include "harness/stats.h"
#include "harness/subprocess.h"
#include "harness/thesis_edit.h"
#include "mesh/mesh_io.h"
#include "methods/deformer.h"
#include "methods/normalization.h"
#include "operators/energy_operator.h"
#include "solvers/linear_solver.h"
#include "solvers/solver_util.h"
#include "systems/normal_system.h"
#include "systems/vertex_ordering.h"

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

// ------------------------------------------------------------------------------------------------ cells
struct CellSpec {
  std::string model, mesh_path, system, backend, ordering;
  int solve_reps = 10, factor_reps = 5;
  double rep_seconds = 2.0;  // stop repeating a phase once it has taken this long in total
  unsigned seed = 1;
  std::size_t memory_limit = 0;  // child's RLIMIT_AS, bytes
  std::string ref_out, ref_in;   // reference solution file (written by the reference cell, read by the others)

  std::vector<std::string> to_args() const {
    return {"--cell",        "--model",       model,
            "--mesh",        mesh_path,       "--system",
            system,          "--backend",     backend,
            "--ordering",    ordering,        "--solve-reps",
            std::to_string(solve_reps),       "--factor-reps",
            std::to_string(factor_reps),      "--rep-seconds",
            fmt::format("{}", rep_seconds),   "--seed",
            std::to_string(seed),             "--memory-limit",
            std::to_string(memory_limit),     "--ref-out",
            ref_out.empty() ? "-" : ref_out,  "--ref-in",
            ref_in.empty() ? "-" : ref_in};
  }
  static CellSpec from_args(const Args& a) {
    CellSpec s;
    s.model = a.get("--model", "");
    s.mesh_path = a.get("--mesh", "");
    s.system = a.get("--system", "lap");
    s.backend = a.get("--backend", kReferenceBackend);
    s.ordering = a.get("--ordering", "default");
    s.solve_reps = std::max(1, int(a.number("--solve-reps", 10)));
    s.factor_reps = std::max(1, int(a.number("--factor-reps", 5)));
    s.rep_seconds = a.number("--rep-seconds", 2.0);
    s.seed = unsigned(a.number("--seed", 1));
    s.memory_limit = std::size_t(a.number("--memory-limit", 0));
    s.ref_out = a.get("--ref-out", "-");
    s.ref_in = a.get("--ref-in", "-");
    if (s.ref_out == "-") s.ref_out.clear();
    if (s.ref_in == "-") s.ref_in.clear();
    if (s.mesh_path.empty()) throw Error("cell: missing --mesh");
    return s;
  }
  std::string key() const { return fmt::format("{}/{}/{}/{}", model, system, backend, ordering); }
};

// One cell's result: named numbers (NaN = not measured) plus status strings.
struct CellResult {
  std::string status = "ok", message, ordering_used, exit;
  std::map<std::string, double> v;
  bool ok() const { return status == "ok"; }
  double get(const std::string& k) const {
    auto it = v.find(k);
    return it == v.end() ? kNaN : it->second;
  }
};

// Every measure in output order, with its unit; `core` ones are kept (empty) for cells that did not run.
struct MeasureDef {
  const char* name;
  const char* unit;
  bool core;
};
const std::vector<MeasureDef>& measure_defs() {
  static const std::vector<MeasureDef> d = {
      {"vertices", "count", false},         {"n", "count", false},
      {"nnz", "count", false},              {"rhs_cols", "count", false},
      {"build_s", "s", false},              {"order_s", "s", false},
      {"analyze_s", "s", true},             {"factorize_s", "s", true},
      {"factorize_min_s", "s", false},      {"factorize_reps", "count", false},
      {"solve_s", "s", true},               {"solve_min_s", "s", false},
      {"solve_reps", "count", false},       {"nnz_factor", "count", true},
      {"factor_flops", "flop", false},      {"gflops", "GFlop/s", false},
      {"matrix_bytes", "bytes", false},     {"factor_bytes", "bytes", true},
      {"baseline_rss_bytes", "bytes", false}, {"peak_rss_bytes", "bytes", true},
      {"ru_maxrss_bytes", "bytes", false},  {"iterations", "count", false},
      {"residual", "relative", true},       {"residual_synthetic", "relative", false},
      {"error_exact", "relative", true},    {"error_vs_cholmod", "relative", false},
      {"cell_wall_s", "s", false},          {"load_avg_1m", "count", false},
  };
  return d;
}

std::string encode(const CellResult& r) {
  std::string o = "DBSOLV status=" + pct_encode(r.status) + " message=" + pct_encode(r.message) +
                  " ordering_used=" + pct_encode(r.ordering_used);
  for (const auto& [k, x] : r.v) o += fmt::format(" {}={}", k, std::isnan(x) ? std::string("nan") : fmt::format("{}", x));
  return o;
}

CellResult decode(const std::string& out) {
  CellResult r;
  for (const auto& [k, val] : parse_result_line(out, "DBSOLV")) {
    if (k == "status") r.status = val;
    else if (k == "message") r.message = val;
    else if (k == "ordering_used") r.ordering_used = val;
    else r.v[k] = val == "nan" ? kNaN : std::stod(val);
  }
  return r;
}

// Unknown u's coordinate c in the solver layout: LAP keeps x, y, z as three columns, TF interleaves them.
inline double& at(DenseMat& M, int block, int u, int c) { return block == 1 ? M(u, c) : M(3 * u + c, 0); }

// Per-vertex positions (#V x 3) from a solution in the solver layout (every vertex is an unknown here).
DenseMat to_vertices(DenseMat& x, const Unknowns& unk, int block, int nv) {
  DenseMat P(nv, 3);
  for (int v = 0; v < nv; ++v)
    for (int c = 0; c < 3; ++c) P(v, c) = at(x, block, unk.unknown_of[v], c);
  return P;
}

double rel_residual(const SpMat& upper, const DenseMat& x, const DenseMat& b) {
  const DenseMat r = upper.selfadjointView<Eigen::Upper>() * x - b;
  const double nb = b.norm();
  return nb > 0 ? r.norm() / nb : r.norm();
}

// Repeats `f` (at least once, at most `reps` times, and no more once `budget_s` seconds have been spent);
// returns {median, min, count}.
template <class F>
std::tuple<double, double, int> repeat_timed(int reps, double budget_s, F&& f) {
  std::vector<double> t;
  double total = 0;
  for (int i = 0; i < reps; ++i) {
    Timer tm;
    f();
    t.push_back(tm.seconds());
    total += t.back();
    if (total >= budget_s) break;
  }
  return {median(t), *std::min_element(t.begin(), t.end()), int(t.size())};
}

CellResult measure_cell(const CellSpec& s) {
  CellResult r;
  const Mesh mesh = read_mesh(s.mesh_path);
  validate_mesh(mesh);
  const Edit edit = make_thesis_edit(mesh);
  const int nv = mesh.num_vertices();
  const Normalization norm = Normalization::fit(mesh.V);
  const Points Vn = norm.apply(mesh.V);
  const Adjacency adj = vertex_adjacency(mesh);
  const auto kinds = classify(edit, ConstraintMode::Soft);
  check_every_component_anchored(adj, kinds);
  Unknowns unk = make_unknowns(kinds, 1.0);

  SolverOptions so;
  const EnergyKind kind = parse_energy(s.system);
  so.block_size = kind == EnergyKind::Lap ? 1 : 3;
  so.ordering = s.ordering;
  double order_s = 0;
  if (s.ordering.rfind("vertex-", 0) == 0) {
    Timer t;
    order_unknowns(adj, unk, s.ordering.substr(7));
    order_s = t.seconds();
    so.ordering = "natural";
  }

  const EnergyOperator op(Vn, mesh.F, adj, kind, EnergyOptions{});
  Timer tb;
  const NormalSystem sys = build_normal_system(op, unk, Build::Structured);
  const double build_s = tb.seconds();
  const int b = sys.block, cols = sys.rhs_cols;
  const Index n = Index(sys.n());

  // The deformation's right-hand side: the full drag (soft constraints: no hard vertices, no C term).
  const Mat4 T = norm.conjugate(edit.transform);
  DenseMat rhs = sys.g0;
  const double w2 = unk.soft_weight * unk.soft_weight;
  for (int v : unk.soft_vertices) {
    const Vec3 p = Vn.row(v).transpose();
    const Vec3 q = edit.roles[v] == Role::Handle ? apply(T, p) : p;
    for (int c = 0; c < 3; ++c) at(rhs, b, unk.unknown_of[v], c) += w2 * q(c);
  }
  // Synthetic right-hand side with a known solution: x_ref per vertex (so every numbering sees the same one).
  std::mt19937_64 rng(s.seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  DenseMat xref(n, cols);
  for (int v = 0; v < nv; ++v)
    for (int c = 0; c < 3; ++c) at(xref, b, unk.unknown_of[v], c) = uni(rng);
  const DenseMat bsyn = sys.K.selfadjointView<Eigen::Upper>() * xref;

  r.v["vertices"] = nv;
  r.v["n"] = n;
  r.v["nnz"] = double(sys.K.nonZeros());
  r.v["rhs_cols"] = cols;
  r.v["build_s"] = build_s;
  r.v["order_s"] = order_s;
  r.v["matrix_bytes"] = double(sparse_bytes(sys.K));
  r.v["baseline_rss_bytes"] = double(current_rss_bytes());

  auto solver = make_solver(s.backend, so);
  Timer ta;
  solver->analyze(sys.K);
  r.v["analyze_s"] = order_s + ta.seconds();
  auto [fmed, fmin, fn] = repeat_timed(s.factor_reps, s.rep_seconds, [&] { solver->factorize(sys.K); });
  r.v["factorize_s"] = fmed;
  r.v["factorize_min_s"] = fmin;
  r.v["factorize_reps"] = fn;
  DenseMat x;
  auto [smed, smin, sn] = repeat_timed(s.solve_reps, s.rep_seconds, [&] { solver->solve(rhs, x); });
  r.v["solve_s"] = smed;
  r.v["solve_min_s"] = smin;
  r.v["solve_reps"] = sn;
  const FactorStats st = solver->stats();
  r.v["iterations"] = st.iterations;
  DenseMat xs;
  solver->solve(bsyn, xs);
  r.v["peak_rss_bytes"] = double(peak_rss_bytes());  // before anything below allocates

  r.ordering_used = st.ordering_used;
  if (s.ordering.rfind("vertex-", 0) == 0) r.ordering_used = s.ordering.substr(7) + "-vertex-graph";
  r.v["nnz_factor"] = double(st.nnz_factor);
  r.v["factor_flops"] = st.flops > 0 ? st.flops : kNaN;
  r.v["gflops"] = st.flops > 0 && fmin > 0 ? st.flops / fmin / 1e9 : kNaN;  // at the fastest repetition
  r.v["factor_bytes"] = double(st.factor_bytes);
  if (solver_info(s.backend).family != "iterative") r.v.erase("iterations");
  r.v["residual"] = rel_residual(sys.K, x, rhs);
  r.v["residual_synthetic"] = rel_residual(sys.K, xs, bsyn);
  r.v["error_exact"] = (xs - xref).norm() / xref.norm();

  const DenseMat P = to_vertices(x, unk, b, nv);
  if (!s.ref_out.empty())
    write_atomically(s.ref_out, [&](std::ostream& o) {
      o.write(reinterpret_cast<const char*>(P.data()), std::streamsize(P.size() * sizeof(double)));
    }, true);
  if (!s.ref_in.empty()) {
    std::ifstream in(s.ref_in, std::ios::binary);
    DenseMat R(nv, 3);
    if (in.read(reinterpret_cast<char*>(R.data()), std::streamsize(R.size() * sizeof(double))))
      r.v["error_vs_cholmod"] = (P - R).norm() / R.norm();
  } else if (!s.ref_out.empty()) {
    r.v["error_vs_cholmod"] = 0.0;
  }
  return r;
}

int cell_main(int argc, char** argv) {
  CellResult r;
  const harness::CellOutcome o = harness::run_guarded_cell([&] {
    const CellSpec s = CellSpec::from_args(parse_args(argc, argv, 1, {"--cell"}));
    harness::limit_address_space(s.memory_limit);
    r = measure_cell(s);
  });
  if (o.status != "ok") {
    r.status = o.status;
    r.message = o.message;
  }
  if (std::isnan(r.get("peak_rss_bytes"))) r.v["peak_rss_bytes"] = double(peak_rss_bytes());
  std::cout << '\n' << encode(r) << std::endl;
  return o.exit_code;
}

CellResult run_in_child(const CellSpec& s, double timeout_s) {
  std::vector<std::string> argv{self_executable()};
  for (auto& a : s.to_args()) argv.push_back(a);
  const ChildRun c = run_child(argv, timeout_s);
  CellResult r;
  bool decoded = false;
  try {
    r = decode(c.out);
    decoded = true;
  } catch (const std::exception&) {
  }
  if (!decoded || c.timed_out || c.term_signal) {
    r = CellResult{};
    r.status = "error";
    r.message = fmt::format("child {}; stderr: {}", c.describe(), c.stderr_tail(400));
  }
  r.exit = c.describe();
  r.v["ru_maxrss_bytes"] = double(c.ru_maxrss_bytes);
  r.v["cell_wall_s"] = c.wall_s;
  return r;
}

// ------------------------------------------------------------------------------------------------ driver
double load_avg() {
  std::ifstream la("/proc/loadavg");
  double x = kNaN;
  la >> x;
  return x;
}

struct Tier {
  std::string label, path;
};

struct Config {
  fs::path data, results;
  std::string out, md;
  bool full = false, write_md = true;
  std::vector<std::string> tiers, systems, backends, orderings, blas_compare;
  double dense_max_n = 4000, poor_ordering_max_n = 20000, iterative_max_n = 20000, cell_timeout = 300,
         cell_memory_mb = 6144;
  int solve_reps = 10, factor_reps = 5;
  double rep_seconds = 2.0;
  unsigned seed = 1;
};

struct Record {
  std::string model, system, backend, family, ordering;
  double vertices = kNaN, n = kNaN;
  CellResult res;
};

std::vector<Tier> tiers_for(const Config& cfg) {
  const std::string m = (cfg.data / "meshes").string(), g = (cfg.data / "generated").string();
  const std::vector<Tier> all = {{"hand", m + "/hand.off"},
                                 {"man", m + "/man.off"},
                                 {"armadillo", m + "/armadillo.off"},
                                 {"armadillo_loop1", g + "/armadillo_loop1.off"}};
  std::vector<std::string> want = cfg.tiers;
  if (want.empty()) {
    want = {"hand", "man", "armadillo"};
    if (cfg.full) want.push_back("armadillo_loop1");
  }
  std::vector<Tier> out;
  for (const auto& w : want) {
    auto it = std::find_if(all.begin(), all.end(), [&](const Tier& t) { return t.label == w; });
    if (it == all.end()) throw InputError(fmt::format("unknown tier '{}' (hand, man, armadillo, armadillo_loop1)", w));
    out.push_back(*it);
  }
  return out;
}

// Orderings of one backend, reference first for CHOLMOD.
std::vector<std::string> orderings_for(const Config& cfg, const SolverInfo& info) {
  std::vector<std::string> o = info.orderings;
  const bool sparse_direct = info.family == "sparse-cholesky" || info.family == "sparse-lu";
  if (sparse_direct && contains(o, "natural")) o.push_back(kVertexOrdering);
  if (info.family == "dense" || info.family == "iterative") o = {"default"};  // nothing to order
  if (!cfg.orderings.empty()) {
    std::vector<std::string> keep;
    for (const auto& x : o)
      if (contains(cfg.orderings, x)) keep.push_back(x);
    o = keep;
  }
  return o;
}

void log_record(const Record& r) {
  const CellResult& c = r.res;
  const std::string key = fmt::format("{}/{}/{}/{}", r.model, r.system, r.backend, r.ordering);
  if (c.ok())
    std::cerr << fmt::format(
        "[solvers] {:52s} n={:7.0f} analyze {:8.4f} s  factorize {:8.4f} s  solve {:9.5f} s  nnzL {:10.0f}  "
        "{:6.2f} GF/s  peak {:7.1f} MiB  res {:.1e}  err {:.1e}\n",
        key, c.get("n"), c.get("analyze_s"), c.get("factorize_s"), c.get("solve_s"), c.get("nnz_factor"),
        c.get("gflops"), c.get("peak_rss_bytes") / kMiB, c.get("residual"), c.get("error_exact"));
  else
    std::cerr << fmt::format("[solvers] {:52s} {}\n", key,
                             c.message.rfind(c.status, 0) == 0 ? c.message : c.status + ": " + c.message);
}

std::vector<Record> run_grid(const Config& cfg) {
  std::vector<Record> recs;
  const fs::path refdir = cfg.results / "cells" / "solvers";
  fs::create_directories(refdir);
  for (const Tier& tier : tiers_for(cfg)) {
    double nv = kNaN;
    std::string load_error;
    if (!fs::exists(tier.path)) {
      load_error = fmt::format("mesh {} not found (run scripts/data.sh)", tier.path);
    } else {
      try {
        nv = read_mesh(tier.path).num_vertices();
      } catch (const std::exception& e) {
        load_error = e.what();
      }
    }
    for (const auto& system : cfg.systems) {
      const double block = system == "lap" ? 1 : 3;
      const std::string ref = (refdir / fmt::format("reference_{}_{}.bin", tier.label, system)).string();
      fs::remove(ref);
      bool have_ref = false;
      for (const auto& backend : cfg.backends) {
        const SolverInfo info = solver_info(backend);
        std::string default_used;  // what "default" resolved to for this backend (from its cell)
        for (const auto& ordering : orderings_for(cfg, info)) {
          Record rec{tier.label, system, backend, info.family, ordering, nv, nv * block, {}};
          const bool is_ref = backend == kReferenceBackend && ordering == "default";
          if (!load_error.empty()) {
            rec.res.status = "error";
            rec.res.message = load_error;
          } else if (ordering != "default" && ordering == default_used) {
            rec.res.status = "skipped";
            rec.res.message = fmt::format("skipped: same as the default ordering ({}), measured in that row", ordering);
          } else if (info.family == "dense" && rec.n > cfg.dense_max_n) {
            rec.res.status = "skipped";
            rec.res.message = fmt::format("skipped: dense over limit (n = {:.0f} > --dense-max-n {:.0f})", rec.n,
                                          cfg.dense_max_n);
          } else if (info.family == "iterative" && rec.n > cfg.iterative_max_n) {
            rec.res.status = "skipped";
            rec.res.message = fmt::format(
                "skipped: iterative over limit (n = {:.0f} > --iterative-max-n {:.0f}; CG iterations grow ~n here)",
                rec.n, cfg.iterative_max_n);
          } else if (info.family != "dense" && info.family != "iterative" &&
                     (ordering == "natural" || (backend == "eigen_sparse_lu" && ordering == "amd")) &&
                     rec.n > cfg.poor_ordering_max_n) {
            rec.res.status = "skipped";
            rec.res.message = fmt::format(
                "skipped: {} ordering fills in badly for {} (n = {:.0f} > --poor-ordering-max-n {:.0f})", ordering,
                backend, rec.n, cfg.poor_ordering_max_n);
          } else {
            CellSpec s;
            s.model = tier.label;
            s.mesh_path = tier.path;
            s.system = system;
            s.backend = backend;
            s.ordering = ordering;
            s.solve_reps = cfg.solve_reps;
            s.factor_reps = cfg.factor_reps;
            s.rep_seconds = cfg.rep_seconds;
            s.seed = cfg.seed;
            s.memory_limit = std::size_t(cfg.cell_memory_mb * kMiB);
            if (is_ref) s.ref_out = ref;
            else if (have_ref) s.ref_in = ref;
            const double load = load_avg();
            rec.res = run_in_child(s, cfg.cell_timeout);
            rec.res.v["load_avg_1m"] = load;
            if (is_ref && rec.res.ok()) have_ref = true;
            if (ordering == "default" && rec.res.ok()) default_used = rec.res.ordering_used;
          }
          log_record(rec);
          recs.push_back(std::move(rec));
        }
      }
      fs::remove(ref);
    }
  }
  return recs;
}

void write_csv(const std::string& path, const std::vector<Record>& recs) {
  CsvTable csv;
  for (const Record& r : recs) {
    for (const MeasureDef& m : measure_defs()) {
      double x = r.res.get(m.name);
      if (std::string(m.name) == "vertices" && std::isnan(x)) x = r.vertices;
      if (std::string(m.name) == "n" && std::isnan(x)) x = r.n;
      const bool always = m.core || std::string(m.name) == "vertices" || std::string(m.name) == "n";
      if (std::isnan(x) && !(always)) continue;
      csv.add({{"model", r.model},
               {"vertices", std::isnan(r.vertices) ? "" : num(r.vertices)},
               {"system", r.system},
               {"backend", r.backend},
               {"family", r.family},
               {"ordering", r.ordering},
               {"ordering_used", r.res.ordering_used},
               {"measure", m.name},
               {"value", std::isnan(x) ? "" : num(x)},
               {"unit", m.unit},
               {"status", r.res.status},
               {"message", r.res.message}});
    }
  }
  if (!csv.empty()) csv.write(path);
}

// ------------------------------------------------------------------------------------------------ CSV reading
// Minimal RFC 4180 reader for CSVs this driver wrote (quoted fields, doubled quotes, no embedded newlines).
std::vector<std::map<std::string, std::string>> read_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot read " + path);
  auto fields = [](const std::string& line) {
    std::vector<std::string> f;
    std::string cur;
    bool q = false;
    for (std::size_t i = 0; i < line.size(); ++i) {
      const char c = line[i];
      if (q) {
        if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') cur += '"', ++i;
        else if (c == '"') q = false;
        else cur += c;
      } else if (c == '"') {
        q = true;
      } else if (c == ',') {
        f.push_back(cur);
        cur.clear();
      } else if (c != '\r') {
        cur += c;
      }
    }
    f.push_back(cur);
    return f;
  };
  std::string line;
  std::getline(in, line);
  const auto header = fields(line);
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const auto f = fields(line);
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < header.size() && i < f.size(); ++i) row[header[i]] = f[i];
    rows.push_back(std::move(row));
  }
  return rows;
}

// Records of a CSV this driver wrote (for --summarize), in file order, plus the provenance of its first row.
std::vector<Record> read_records(const std::string& path, Provenance& prov) {
  std::vector<Record> recs;
  std::map<std::string, std::size_t> index;
  bool first = true;
  for (const auto& row : read_csv(path)) {
    auto get = [&](const char* k) {
      auto it = row.find(k);
      return it == row.end() ? std::string() : it->second;
    };
    if (first) {
      prov.git_sha = get("git_sha");
      prov.blas = get("blas");
      prov.blas_core = get("blas_core");
      prov.blas_coretype_env = get("blas_coretype_env") == "auto" ? "" : get("blas_coretype_env");
      prov.blas_threads = std::atoi(get("blas_threads").c_str());
      prov.build_threads = std::atoi(get("build_threads").c_str());
      prov.hardware_threads = std::atoi(get("hardware_threads").c_str());
      prov.cpu = get("cpu");
      prov.compiler = get("compiler");
      prov.timestamp = get("timestamp");
      first = false;
    }
    const std::string key = get("model") + "/" + get("system") + "/" + get("backend") + "/" + get("ordering");
    auto it = index.find(key);
    if (it == index.end()) {
      Record r;
      r.model = get("model");
      r.system = get("system");
      r.backend = get("backend");
      r.family = get("family");
      r.ordering = get("ordering");
      r.vertices = get("vertices").empty() ? kNaN : std::stod(get("vertices"));
      r.res.status = get("status");
      r.res.message = get("message");
      r.res.ordering_used = get("ordering_used");
      it = index.emplace(key, recs.size()).first;
      recs.push_back(std::move(r));
    }
    Record& r = recs[it->second];
    const std::string v = get("value");
    r.res.v[get("measure")] = v.empty() ? kNaN : std::stod(v);
    if (get("measure") == "n") r.n = r.res.v["n"];
  }
  return recs;
}

// A BLAS variant run read back: its provenance and (model/system/backend/ordering/measure) -> value.
struct Variant {
  std::string file, coretype_env, blas_core, blas;
  std::map<std::string, double> values;
};

Variant read_variant(const std::string& path) {
  Variant v;
  v.file = path;
  for (const auto& row : read_csv(path)) {
    auto get = [&](const char* k) {
      auto it = row.find(k);
      return it == row.end() ? std::string() : it->second;
    };
    v.coretype_env = get("blas_coretype_env");
    v.blas_core = get("blas_core");
    v.blas = get("blas");
    if (get("status") != "ok" || get("value").empty()) continue;
    v.values[fmt::format("{}/{}/{}/{}/{}", get("model"), get("system"), get("backend"), get("ordering"),
                         get("measure"))] = std::stod(get("value"));
  }
  return v;
}

// ------------------------------------------------------------------------------------------------ Markdown
const Record* find(const std::vector<Record>& recs, const std::string& model, const std::string& system,
                   const std::string& backend, const std::string& ordering) {
  for (const auto& r : recs)
    if (r.model == model && r.system == system && r.backend == backend && r.ordering == ordering) return &r;
  return nullptr;
}

double value(const Record* r, const char* m) { return r && r->res.ok() ? r->res.get(m) : kNaN; }

std::string fnum(double x, const char* f = "{:.3g}") { return std::isnan(x) ? "-" : fmt::format(fmt::runtime(f), x); }
std::string fsec(double x) {
  if (std::isnan(x)) return "-";
  if (x < 1e-3) return fmt::format("{:.1f} us", x * 1e6);
  if (x < 1) return fmt::format("{:.2f} ms", x * 1e3);
  return fmt::format("{:.2f} s", x);
}
std::string fratio(double a, double b) { return a > 0 && b > 0 ? fmt::format("{:.2f}", a / b) : "-"; }

std::vector<std::string> models_of(const std::vector<Record>& recs) {
  std::vector<std::string> m;
  for (const auto& r : recs)
    if (!contains(m, r.model)) m.push_back(r.model);
  return m;
}

// Geometric mean of positive values (NaN when none).
double geomean(const std::vector<double>& v) {
  double s = 0;
  int k = 0;
  for (double x : v)
    if (x > 0 && std::isfinite(x)) s += std::log(x), ++k;
  return k ? std::exp(s / k) : kNaN;
}

std::pair<double, double> minmax(const std::vector<double>& v) {
  double lo = kNaN, hi = kNaN;
  for (double x : v)
    if (std::isfinite(x)) {
      lo = std::isnan(lo) ? x : std::min(lo, x);
      hi = std::isnan(hi) ? x : std::max(hi, x);
    }
  return {lo, hi};
}

std::string verdict_word(double ratio_geo) {
  if (std::isnan(ratio_geo)) return "not measured";
  if (ratio_geo < 0.95) return "**refuted** (Cholesky is slower)";
  if (ratio_geo < 1.05) return "**no measurable difference** (within 5%)";
  if (ratio_geo < 1.5) return "**confirmed**: Cholesky is slightly faster";
  return "**confirmed, and understated**: Cholesky is clearly faster, not just slightly";
}

// One paragraph stating the measured verdict from the ratios (> 1: Cholesky faster).
std::string verdict_prose(double g_lu, double g_bk, double g_sparse, const std::vector<double>& lu,
                          const std::vector<double>& bk, const std::vector<double>& sparse) {
  auto all_above = [](const std::vector<double>& v, double t) {
    bool any = false;
    for (double x : v)
      if (std::isfinite(x)) {
        if (x <= t) return false;
        any = true;
      }
    return any;
  };
  std::string s = "**Measured verdict.** ";
  if (std::isnan(g_lu) && std::isnan(g_sparse)) return s + "Not measured (no Cholesky / LU pair ran).";
  const bool holds = all_above(lu, 1.0) && all_above(bk, 1.0) && all_above(sparse, 1.0);
  s += holds ? "The claim holds on every system measured: Cholesky factorizes faster than LU and than Bunch-Kaufman. "
             : "The claim does not hold on every system measured (see the ranges). ";
  s += fmt::format(
      "{}: dense LU took {}x the time of dense Cholesky and the fastest "
      "sparse LU {}x the fastest sparse Cholesky (geometric means), as expected from LU's doubled flop count (dense: "
      "2n^3/3 against n^3/3) and its doubled factor (L and U). ",
      std::min(g_lu, g_sparse) >= 1.5 ? "Against LU the gap is larger than \"slightly\"" : "Against LU",
      fnum(g_lu, "{:.2f}"), fnum(g_sparse, "{:.2f}"));
  s += fmt::format(
      "Bunch-Kaufman LDL^T does the same n^3/3 flops as Cholesky; its {}x comes from the symmetric pivot search "
      "and the less regular blocking of dsytrf{}",
      fnum(g_bk, "{:.2f}"),
      g_bk < 1.5 ? ", and is where \"slightly\" fits." : ": clearly slower as well, not slightly.");
  return s;
}

// The summary reads the minimum over a cell's repetitions: on a shared machine interference only adds time.
const char* const kFactor = "factorize_min_s";
const char* const kSolve = "solve_min_s";

void write_md(const Config& cfg, const std::vector<Record>& recs, const std::vector<Variant>& variants,
              const Provenance& p) {
  std::ostringstream o;
  const auto models = models_of(recs);
  std::vector<double> loads;
  for (const auto& r : recs)
    if (!std::isnan(r.res.get("load_avg_1m"))) loads.push_back(r.res.get("load_avg_1m"));
  const double load_med = median(loads);
  const double load_max = loads.empty() ? kNaN : *std::max_element(loads.begin(), loads.end());
  o << "# Solver choice for the LAP and TF systems (issue 4)\n\n"
    << "Generated by `exp_solvers` (experiments/solvers.cpp) from `results/solvers.csv`; do not edit by hand.\n\n"
    << "- Systems: the thesis edit of every tier (whole-mesh ROI, 100 handle vertices at one extreme of the longest axis, 100 anchors at the other), soft "
       "constraints (w = 1), structured build: K is #V x #V (lap, 3 right-hand-side columns) or 3#V x 3#V "
       "(tf, 1 column).\n"
    << "- Every cell (tier, system, backend, ordering) ran in its own child process: peak RSS is that process' "
       "VmHWM (mesh + system + solver). Factorize: up to " << cfg.factor_reps
    << " repetitions; solve: up to " << cfg.solve_reps
    << " solves of the deformation's right-hand side (each phase stops repeating once it has taken "
    << cfg.rep_seconds << " s). "
       "Tables below show the minimum over the repetitions (interference from other jobs only adds time; "
       "the CSV has the medians too: `factorize_s`, `solve_s`). One thread (BLAS, OpenMP, assembly) unless `--threads`.\n"
    << "- Errors: `residual` = ||Kx-b||/||b|| (deformation RHS); `error_exact` = ||x-x_ref||/||x_ref|| for "
       "b = K x_ref with a seeded random x_ref; `error_vs_cholmod` = deformed positions against CHOLMOD "
       "supernodal (default ordering) of the same system.\n"
    << fmt::format("- Machine: {}; {} threads; {}; BLAS {} core {} (OPENBLAS_CORETYPE={}), {} BLAS threads; "
                   "git {}.\n",
                   p.cpu, p.hardware_threads, p.compiler, p.blas, p.blas_core,
                   p.blas_coretype_env.empty() ? "unset" : p.blas_coretype_env, p.blas_threads, p.git_sha)
    << (std::isnan(load_med)
            ? std::string("- Load average: not recorded.\n\n")
            : fmt::format("- Load average (1 min) before each cell: median {:.1f}, max {:.1f}, on {} hardware "
                          "threads{}\n\n",
                          load_med, load_max, p.hardware_threads,
                          load_med > 0.5 * p.hardware_threads
                              ? fmt::format(": the machine was shared with other jobs, so single timings carry noise "
                                            "of tens of percent (cells above ~{} s had one or two repetitions); "
                                            "ratios within 0.8-1.25 are not significant.",
                                            cfg.rep_seconds / 2)
                              : "."));

  // ---------------------------------------------------------------- dense verdict
  o << "## Verdict on the thesis' claim (section 2.2.3: Cholesky is slightly faster than LU and "
       "Bunch-Kaufman)\n\n";
  std::vector<double> lu_dense, bk_dense, lu_sparse_cm, lu_sparse_eig;
  auto range = [](const std::vector<double>& v) {
    auto [lo, hi] = minmax(v);
    return std::isnan(lo) ? std::string("-") : fmt::format("{:.2f}-{:.2f}", lo, hi);
  };
  std::ostringstream dense;
  dense << "### Dense factorizations (same matrix, same BLAS)\n\n"
        << "| tier | system | n | LAPACK dpotrf (LL^T) | Eigen LLT | LAPACK dsytrf (Bunch-Kaufman LDL^T) | "
           "LAPACK dgetrf (LU) | LU / LL^T | BK / LL^T | Eigen LLT / dpotrf |\n"
        << "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  bool any_dense = false;
  for (const auto& m : models)
    for (const auto& sys : cfg.systems) {
      const Record* pot = find(recs, m, sys, "lapack_potrf", "default");
      const Record* llt = find(recs, m, sys, "dense_llt", "default");
      const Record* bk = find(recs, m, sys, "dense_ldlt_bk", "default");
      const Record* lu = find(recs, m, sys, "dense_lu", "default");
      const double tp = value(pot, kFactor), tl = value(llt, kFactor), tb = value(bk, kFactor),
                   tu = value(lu, kFactor);
      if (std::isnan(tp) && std::isnan(tl) && std::isnan(tb) && std::isnan(tu)) continue;
      any_dense = true;
      const double chol = !std::isnan(tp) ? tp : tl;  // same-library Cholesky when measured
      lu_dense.push_back(tu / chol);
      bk_dense.push_back(tb / chol);
      dense << fmt::format("| {} | {} | {:.0f} | {} | {} | {} | {} | {} | {} | {} |\n", m, sys,
                           value(lu ? lu : pot, "n"), fsec(tp), fsec(tl), fsec(tb), fsec(tu), fratio(tu, chol),
                           fratio(tb, chol), fratio(tl, tp));
    }
  if (!any_dense) dense << "| (no dense cell ran: every tier is over --dense-max-n) | | | | | | | | | |\n";
  dense << "\nRatios are factorize-time quotients (> 1: Cholesky faster). Flop counts: LL^T and LDL^T n^3/3, "
           "LU 2n^3/3.\n\n";

  // ---------------------------------------------------------------- sparse verdict
  // Each backend at its default ordering, and at its best measured ordering (least factorize time): an LU code
  // given an ordering meant for Cholesky (e.g. AMD for SparseLU, which wants COLAMD) is not a fair opponent.
  auto best_of = [&](const std::string& m, const std::string& sys, const std::string& be) -> const Record* {
    const Record* best = nullptr;
    for (const auto& r : recs)
      if (r.model == m && r.system == sys && r.backend == be && r.res.ok() &&
          (!best || r.res.get(kFactor) < best->res.get(kFactor)))
        best = &r;
    return best;
  };
  auto best_family = [&](const std::string& m, const std::string& sys, const std::string& fam) -> const Record* {
    const Record* best = nullptr;
    for (const auto& r : recs)
      if (r.model == m && r.system == sys && r.family == fam && r.res.ok() &&
          (!best || r.res.get(kFactor) < best->res.get(kFactor)))
        best = &r;
    return best;
  };
  auto with_ordering = [](const Record* r) {
    return r && r->res.ok() ? fmt::format("{} ({})", fsec(r->res.get(kFactor)), r->ordering) : std::string("-");
  };
  std::vector<double> lu_sparse_any;
  std::ostringstream sparse;
  sparse << "### Sparse factorizations (same matrix)\n\n"
         << "`default`: each backend with its own default ordering; `best`: each backend with the ordering that "
            "factorized fastest among those measured (in parentheses).\n\n"
         << "| tier | system | n | orderings | CHOLMOD supernodal | Eigen simplicial LL^T | UMFPACK | Eigen SparseLU | "
            "UMFPACK / CHOLMOD | SparseLU / Eigen LL^T | nnz(L+U) / nnz(L), UMFPACK / CHOLMOD |\n"
         << "|---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& m : models)
    for (const auto& sys : cfg.systems)
      for (const bool best : {false, true}) {
        const Record* cm = best ? best_of(m, sys, "cholmod_supernodal") : find(recs, m, sys, "cholmod_supernodal", "default");
        const Record* el = best ? best_of(m, sys, "eigen_simplicial_llt") : find(recs, m, sys, "eigen_simplicial_llt", "default");
        const Record* um = best ? best_of(m, sys, "umfpack") : find(recs, m, sys, "umfpack", "default");
        const Record* sl = best ? best_of(m, sys, "eigen_sparse_lu") : find(recs, m, sys, "eigen_sparse_lu", "default");
        const double tc = value(cm, kFactor), te = value(el, kFactor), tu = value(um, kFactor),
                     ts = value(sl, kFactor);
        if (std::isnan(tc) && std::isnan(te) && std::isnan(tu) && std::isnan(ts)) continue;
        if (best) {
          lu_sparse_cm.push_back(tu / tc);
          lu_sparse_eig.push_back(ts / te);
          const Record* bl = best_family(m, sys, "sparse-lu");
          const Record* bc = best_family(m, sys, "sparse-cholesky");
          lu_sparse_any.push_back(value(bl, kFactor) / value(bc, kFactor));
        }
        const double n = value(cm ? cm : um, "n");
        sparse << fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", m, sys, fnum(n, "{:.0f}"),
                              best ? "best" : "default", with_ordering(cm), with_ordering(el), with_ordering(um),
                              with_ordering(sl), fratio(tu, tc), fratio(ts, te),
                              fratio(value(um, "nnz_factor"), value(cm, "nnz_factor")));
      }
  sparse << "\nCHOLMOD / Eigen LL^T store L only; UMFPACK and SparseLU store L and U (nnz counts both).\n\n";

  const double g_lu = geomean(lu_dense), g_bk = geomean(bk_dense), g_cm = geomean(lu_sparse_cm),
               g_eig = geomean(lu_sparse_eig), g_any = geomean(lu_sparse_any);
  o << "| comparison | factorize-time ratio (geometric mean) | range over systems | verdict |\n"
    << "|---|---:|---:|---|\n"
    << fmt::format("| dense LU / dense Cholesky | {} | {} | {} |\n", fnum(g_lu, "{:.2f}"), range(lu_dense),
                   verdict_word(g_lu))
    << fmt::format("| dense Bunch-Kaufman LDL^T / dense Cholesky | {} | {} | {} |\n", fnum(g_bk, "{:.2f}"),
                   range(bk_dense), verdict_word(g_bk))
    << fmt::format("| sparse UMFPACK LU / CHOLMOD supernodal LL^T (best orderings) | {} | {} | {} |\n",
                   fnum(g_cm, "{:.2f}"), range(lu_sparse_cm), verdict_word(g_cm))
    << fmt::format("| sparse Eigen SparseLU / Eigen simplicial LL^T (best orderings) | {} | {} | {} |\n",
                   fnum(g_eig, "{:.2f}"), range(lu_sparse_eig), verdict_word(g_eig))
    << fmt::format("| fastest sparse LU / fastest sparse Cholesky (any backend, any ordering) | {} | {} | {} |\n",
                   fnum(g_any, "{:.2f}"), range(lu_sparse_any), verdict_word(g_any))
    << "\n"
    << verdict_prose(g_lu, g_bk, g_any, lu_dense, bk_dense, lu_sparse_any) << "\n\n"
    << "Dense Cholesky is LAPACK dpotrf where it ran (same library as dgetrf / dsytrf), else Eigen's LLT. "
       "The thesis measured on an AMD64 3000+ (2008) without saying which implementations it compared.\n\n"
    << dense.str() << sparse.str();

  // ---------------------------------------------------------------- per tier table
  o << "## Every backend, default ordering\n\n"
    << "| tier | system | n | backend | ordering used | analyze | factorize | solve | nnz(L) | GFlop/s | factor MiB "
       "| peak RSS MiB | residual | error_exact | vs CHOLMOD | status |\n"
    << "|---|---|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n";
  for (const auto& m : models)
    for (const auto& sys : cfg.systems)
      for (const auto& be : cfg.backends) {
        const Record* r = find(recs, m, sys, be, "default");
        if (!r) continue;
        o << fmt::format("| {} | {} | {:.0f} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", m,
                         sys, r->n, be, r->res.ordering_used.empty() ? "-" : r->res.ordering_used,
                         fsec(value(r, "analyze_s")), fsec(value(r, kFactor)), fsec(value(r, kSolve)),
                         fnum(value(r, "nnz_factor"), "{:.0f}"), fnum(value(r, "gflops"), "{:.2f}"),
                         fnum(value(r, "factor_bytes") / kMiB, "{:.1f}"),
                         fnum(value(r, "peak_rss_bytes") / kMiB, "{:.0f}"), fnum(value(r, "residual"), "{:.1e}"),
                         fnum(value(r, "error_exact"), "{:.1e}"), fnum(value(r, "error_vs_cholmod"), "{:.1e}"),
                         r->res.ok() ? "ok" : r->res.message);
      }

  // ---------------------------------------------------------------- orderings
  o << "\n## Orderings (sparse direct backends, largest tier)\n\n";
  const std::string big = models.empty() ? "" : models.back();
  o << "| system | backend | ordering | ordering used | analyze | factorize | solve | nnz(L) | status |\n"
    << "|---|---|---|---|---:|---:|---:|---:|---|\n";
  for (const auto& sys : cfg.systems)
    for (const auto& r : recs)
      if (r.model == big && r.system == sys && (r.family == "sparse-cholesky" || r.family == "sparse-lu"))
        o << fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", sys, r.backend, r.ordering,
                         r.res.ordering_used.empty() ? "-" : r.res.ordering_used, fsec(value(&r, "analyze_s")),
                         fsec(value(&r, kFactor)), fsec(value(&r, kSolve)),
                         fnum(value(&r, "nnz_factor"), "{:.0f}"), r.res.ok() ? "ok" : r.res.message);
  // Best (backend, ordering) per system and tier for the interactive split: factorize once, solve per frame.
  o << "\n## Fastest choice per tier and system\n\n"
    << "| tier | system | fastest factorize (backend/ordering) | time | fastest solve | time | fastest "
       "analyze+factorize+20 solves | time |\n|---|---|---|---:|---|---:|---|---:|\n";
  for (const auto& m : models)
    for (const auto& sys : cfg.systems) {
      const Record *bf = nullptr, *bs = nullptr, *bt = nullptr;
      double tf = 1e300, ts = 1e300, tt = 1e300;
      for (const auto& r : recs) {
        if (r.model != m || r.system != sys || !r.res.ok()) continue;
        const double f = r.res.get(kFactor), s = r.res.get(kSolve), a = r.res.get("analyze_s");
        if (r.family != "iterative" && f < tf) tf = f, bf = &r;
        if (s < ts) ts = s, bs = &r;
        const double t = a + f + 20 * s;
        if (t < tt) tt = t, bt = &r;
      }
      auto name = [](const Record* r) { return r ? r->backend + "/" + r->ordering : std::string("-"); };
      o << fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} |\n", m, sys, name(bf), bf ? fsec(tf) : "-",
                       name(bs), bs ? fsec(ts) : "-", name(bt), bt ? fsec(tt) : "-");
    }

  // ---------------------------------------------------------------- BLAS
  o << "\n## BLAS kernel set\n\n"
    << fmt::format("This run: {} core **{}** (OPENBLAS_CORETYPE={}). ", p.blas, p.blas_core,
                   p.blas_coretype_env.empty() ? "unset, auto-detected" : p.blas_coretype_env);
  if (variants.empty()) {
    o << "No other kernel set was measured (scripts/experiments.sh runs one when the CPU has AVX-512: "
         "`grep avx512f /proc/cpuinfo`).\n";
  } else {
    o << "The same driver was run again with other `OPENBLAS_CORETYPE` values, restricted to the backends that "
         "call the BLAS (CHOLMOD supernodal, UMFPACK, LAPACK dense) plus Eigen's own dense LLT as a control "
         "(it never calls the BLAS, so its ratio shows the run-to-run noise). Ratio = variant time / this run's "
         "time (< 1: the variant is faster).\n\n";
    for (const Variant& v : variants) {
      o << fmt::format("### {} core {} (OPENBLAS_CORETYPE={}), `{}`\n\n", v.blas, v.blas_core,
                       v.coretype_env, fs::path(v.file).filename().string())
        << "| tier | system | backend | factorize here | factorize variant | ratio | solve here | solve variant "
           "| ratio |\n|---|---|---|---:|---:|---:|---:|---:|---:|\n";
      std::vector<double> fr_blas, fr_ctrl, fr_dense, fr_sparse;
      for (const auto& r : recs) {
        if (r.ordering != "default" || !r.res.ok()) continue;
        const std::string k = fmt::format("{}/{}/{}/{}/", r.model, r.system, r.backend, r.ordering);
        auto it_f = v.values.find(k + std::string(kFactor));
        auto it_s = v.values.find(k + std::string(kSolve));
        if (it_f == v.values.end()) continue;
        const double f0 = r.res.get(kFactor), s0 = r.res.get(kSolve);
        const double f1 = it_f->second, s1 = it_s == v.values.end() ? kNaN : it_s->second;
        (r.backend == "dense_llt" ? fr_ctrl : fr_blas).push_back(f1 / f0);
        if (r.backend != "dense_llt") (r.family == "dense" ? fr_dense : fr_sparse).push_back(f1 / f0);
        o << fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", r.model, r.system, r.backend, fsec(f0),
                         fsec(f1), fratio(f1, f0), fsec(s0), fsec(s1), fratio(s1, s0));
      }
      const double gb = geomean(fr_blas);
      auto [clo, chi] = minmax(fr_ctrl);
      // Noise band: the no-BLAS control's spread, widened to at least +-20% (the control has few cells).
      const double lo = std::min(std::isnan(clo) ? 1.0 : clo, 1.0 / 1.2), hi = std::max(std::isnan(chi) ? 1.0 : chi, 1.2);
      std::string verdict;
      if (std::isnan(gb)) verdict = "not measured";
      else if (gb >= lo && gb <= hi)
        verdict = fmt::format("no measurable difference: the ratio lies inside the noise band {:.2f}-{:.2f} (the "
                              "no-BLAS control's spread, at least +-20%)", lo, hi);
      else
        verdict = fmt::format("{} is {} (outside the noise band {:.2f}-{:.2f})", v.blas_core,
                              gb < 1 ? "faster" : "slower", lo, hi);
      o << fmt::format("\nFactorize ratio, geometric mean over the BLAS-calling cells: **{}** (range {}); Eigen LLT "
                       "control (no BLAS): {} (range {}). Verdict: {}.\n\n",
                       fnum(gb, "{:.2f}"), range(fr_blas), fnum(geomean(fr_ctrl), "{:.2f}"), range(fr_ctrl), verdict)
        << fmt::format("By family: dense LAPACK (dpotrf, dsytrf, dgetrf) {} (range {}); sparse (CHOLMOD supernodal, "
                       "UMFPACK) {} (range {}).\n\n",
                       fnum(geomean(fr_dense), "{:.2f}"), range(fr_dense), fnum(geomean(fr_sparse), "{:.2f}"),
                       range(fr_sparse));
    }
  }
  write_atomically(cfg.md, [&](std::ostream& out) { out << o.str(); });
}

// Pins the thread counts of this run (children inherit them) by re-executing the driver with OMP_NUM_THREADS,
// OPENBLAS_NUM_THREADS and DEFORMBENCH_THREADS (structured assembly) set: the libraries read them when they load,
// and the provenance columns then record what was used. Why 1 by default: on a shared 2-core machine a parallel region waits for a descheduled
// thread (CG with 2 threads measured 100x slower than with 1), and one thread compares algorithms, not schedulers.
void pin_threads(const Args& a, char** argv) {
  const int threads = int(a.number("--threads", 1));
  if (threads <= 0) return;
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

int driver_main(int argc, char** argv) {
  const Args a = parse_args(argc, argv, 1, {"--full", "--no-md", "--summarize"});
  pin_threads(a, argv);
  Config cfg;
  cfg.data = a.get("--data", "data");
  cfg.results = a.get("--results", "results");
  cfg.full = a.has("--full");
  cfg.write_md = !a.has("--no-md");
  cfg.out = a.get("--out", (cfg.results / "solvers.csv").string());
  cfg.md = a.get("--md", (cfg.results / "solvers.md").string());
  cfg.tiers = split_list(a.get("--tiers", ""));
  cfg.systems = split_list(a.get("--systems", "lap,tf"));
  cfg.backends = split_list(a.get("--backends", ""));
  if (cfg.backends.empty()) cfg.backends = solver_names();
  // The reference (CHOLMOD supernodal, default ordering) runs first so every other cell can compare with it.
  if (auto it = std::find(cfg.backends.begin(), cfg.backends.end(), kReferenceBackend); it != cfg.backends.end())
    std::rotate(cfg.backends.begin(), it, it + 1);
  for (const auto& b : cfg.backends) solver_info(b);  // throws for an unknown name
  for (const auto& s : cfg.systems) parse_energy(s);
  cfg.orderings = split_list(a.get("--orderings", ""));
  cfg.blas_compare = split_list(a.get("--blas-compare", ""));
  cfg.dense_max_n = a.number("--dense-max-n", cfg.dense_max_n);
  cfg.poor_ordering_max_n = a.number("--poor-ordering-max-n", cfg.poor_ordering_max_n);
  cfg.iterative_max_n = a.number("--iterative-max-n", cfg.iterative_max_n);
  cfg.cell_timeout = a.number("--cell-timeout-s", cfg.cell_timeout);
  cfg.cell_memory_mb = a.number("--cell-memory-mb", cfg.cell_memory_mb);
  cfg.solve_reps = int(a.number("--solve-reps", cfg.solve_reps));
  cfg.factor_reps = int(a.number("--factor-reps", cfg.factor_reps));
  cfg.rep_seconds = a.number("--rep-seconds", cfg.rep_seconds);
  cfg.seed = unsigned(a.number("--seed", cfg.seed));
  fs::create_directories(cfg.results);
  if (!fs::path(cfg.out).parent_path().empty()) fs::create_directories(fs::path(cfg.out).parent_path());

  std::vector<Record> recs;
  Provenance prov = provenance();
  if (a.has("--summarize")) {
    // Only the summary, from an earlier run's CSV (its own provenance, backends and systems).
    recs = read_records(cfg.out, prov);
    cfg.systems.clear();
    cfg.backends.clear();
    for (const auto& r : recs) {
      if (!contains(cfg.systems, r.system)) cfg.systems.push_back(r.system);
      if (!contains(cfg.backends, r.backend)) cfg.backends.push_back(r.backend);
    }
  } else {
    std::cerr << "[solvers] " << provenance_summary() << fmt::format(" | load {:.1f}", load_avg()) << "\n";
    recs = run_grid(cfg);
    write_csv(cfg.out, recs);
    std::cerr << "[solvers] wrote " << cfg.out << "\n";
  }
  if (cfg.write_md) {
    std::vector<Variant> variants;
    for (const auto& f : cfg.blas_compare) {
      if (!fs::exists(f)) {
        std::cerr << "[solvers] --blas-compare: " << f << " not found, skipped\n";
        continue;
      }
      variants.push_back(read_variant(f));
    }
    write_md(cfg, recs, variants, prov);
    std::cerr << "[solvers] wrote " << cfg.md << "\n";
  }
  int failed = 0;
  for (const auto& r : recs) failed += r.res.status == "error";
  if (failed) std::cerr << fmt::format("[solvers] {} cell(s) failed; see the status/message columns\n", failed);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  ::unsetenv("DEFORMBENCH_ORDERING_CACHE");  // cold analyses: a cached ordering would skip METIS in the cells
  if (argc > 1 && std::string(argv[1]) == "--cell") return cell_main(argc, argv);
  try {
    return driver_main(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "exp_solvers: error: " << e.what() << "\n";
    return exit_code(e);
  }
}
