#include "harness/solver_cell.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "solvers/base/resources.h"
#include "core/provenance.h"
#include "core/timer.h"
#include "edit/edit_io.h"
#include "harness/cpu_timer.h"
#include "harness/positions.h"
#include "harness/thesis_edit.h"
#include "mesh/mesh_io.h"
#include "methods/deform_option_flags.h"
#include "methods/deform_options.h"
#include "methods/deformer.h"
#include "methods/edit_system.h"
#include "methods/normalization.h"
#include "operators/energy_operator.h"
#include "solvers/least_squares.h"
#include "solvers/linear_solver.h"
#include "systems/least_squares_system.h"
#include "systems/matrix_market.h"
#include "systems/normal_system.h"
#include "systems/vertex_ordering.h"

namespace db::harness {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Unknown u's coordinate c in the solver layout: LAP keeps x, y, z as three columns, TF interleaves them.
inline double& at(DenseMat& M, int block, int u, int c) { return block == 1 ? M(u, c) : M(3 * u + c, 0); }

// The thesis edit's system, before any build: what every cell of a tier and system shares.
struct Problem {
  Mesh mesh;
  Edit edit;
  Normalization norm;
  Points Vn;
  Adjacency adj;
  Unknowns unk;
  EnergyKind kind = EnergyKind::Lap;
  int block = 1;
  double order_s = 0, order_cpu_s = 0;  // vertex-graph ordering of the unknowns ("vertex-*" orderings)
};

Problem make_problem(const SolverCell& c) {
  Problem p;
  p.mesh = read_mesh(c.mesh);
  validate_mesh(p.mesh, Manifold::Allowed);  // LAP and TF (uniform) live on the vertex graph
  p.edit = make_thesis_edit(p.mesh);
  p.norm = Normalization::fit(p.mesh.V);
  p.Vn = p.norm.apply(p.mesh.V);
  p.adj = vertex_adjacency(p.mesh);
  const auto kinds = classify(p.edit, ConstraintMode::Soft);
  check_every_component_anchored(p.adj, kinds);
  p.unk = make_unknowns(kinds, 1.0);
  p.kind = parse_enum<EnergyKind>(c.system);
  p.block = p.kind == EnergyKind::Lap ? 1 : 3;
  if (c.ordering.rfind("vertex-", 0) == 0) {
    const CpuTimer tc;
    Timer t;
    order_unknowns(p.adj, p.unk, c.ordering.substr(7));
    p.order_s = t.seconds();
    p.order_cpu_s = tc.seconds();
  }
  return p;
}

// The soft targets of the full drag (normalized coordinates): handle moved, anchors in place.
Vec3 soft_target(const Problem& p, int v) {
  const Vec3 q = p.Vn.row(v).transpose();
  return p.edit.roles[v] == Role::Handle ? apply(p.norm.conjugate(p.edit.transform), q) : q;
}

// The deformation's right-hand side: g0 + w^2 * soft targets (soft constraints: no hard vertices, no C term).
DenseMat drag_rhs(const Problem& p, const NormalSystem& sys) {
  DenseMat rhs = sys.g0;
  const double w2 = p.unk.soft_weight * p.unk.soft_weight;
  for (int v : p.unk.soft_vertices) {
    const Vec3 q = soft_target(p, v);
    for (int c = 0; c < 3; ++c) at(rhs, p.block, p.unk.unknown_of[v], c) += w2 * q(c);
  }
  return rhs;
}

// x_ref per vertex (so every numbering sees the same one).
DenseMat reference_solution(const Problem& p, unsigned seed, int cols) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  DenseMat x(Index(p.block * p.unk.num_unknowns()), cols);
  for (int v = 0; v < p.mesh.num_vertices(); ++v)
    for (int c = 0; c < 3; ++c) at(x, p.block, p.unk.unknown_of[v], c) = uni(rng);
  return x;
}

Points to_vertices(DenseMat& x, const Problem& p) {
  Points P(p.mesh.num_vertices(), 3);
  for (int v = 0; v < p.mesh.num_vertices(); ++v)
    for (int c = 0; c < 3; ++c) P(v, c) = at(x, p.block, p.unk.unknown_of[v], c);
  return P;
}

double rel_residual(const SpMat& upper, const DenseMat& x, const DenseMat& b) {
  const DenseMat r = upper.selfadjointView<Eigen::Upper>() * x - b;
  const double nb = b.norm();
  return nb > 0 ? r.norm() / nb : r.norm();
}

// Repeats `f` (at least once, at most `reps` times, and no more once `budget_s` seconds have been spent).
struct Reps {
  std::vector<double> wall, cpu;  // seconds per repetition; CPU time of this process (harness/cpu_timer.h)
  double min() const { return wall.empty() ? kNaN : *std::min_element(wall.begin(), wall.end()); }
};
template <class F>
Reps repeat_timed(int reps, double budget_s, F&& f) {
  Reps r;
  double total = 0;
  for (int i = 0; i < reps; ++i) {
    const CpuTimer tc;
    Timer tm;
    f();
    r.wall.push_back(tm.seconds());
    r.cpu.push_back(tc.seconds());
    total += r.wall.back();
    if (total >= budget_s) break;
  }
  return r;
}

// What a cell's system is, whichever source built it.
struct SystemFacts {
  double vertices = kNaN, build_s = 0, build_cpu_s = 0, order_s = 0, order_cpu_s = 0;
};

void add_system(CellResult& r, const SystemFacts& f, const SpMat& K, int rhs_cols) {
  r.set("vertices", f.vertices, "count");
  r.set("n", static_cast<double>(K.rows()), "count");
  r.set("nnz", double(K.nonZeros()), "count");
  r.set("rhs_cols", rhs_cols, "count");
  r.set("build_s", f.build_s, "s");
  r.set("build_cpu_s", f.build_cpu_s, "s");
  r.set("order_s", f.order_s, "s");
  r.set("matrix_bytes", double(sparse_bytes(K)), "bytes");
  r.set("baseline_rss_bytes", double(current_rss_bytes()), "bytes");
}

// What the factorization and solve phases measured, the same for every kind of solver.
struct Phases {
  double analyze_s = 0, analyze_cpu_s = 0;
  Reps factorize, solve;
  FactorStats stats;
};

void add_phases(CellResult& r, const Phases& ph) {
  const Reps &f = ph.factorize, &s = ph.solve;
  r.set("analyze_s", ph.analyze_s, "s");
  r.set("analyze_cpu_s", ph.analyze_cpu_s, "s");
  set_spread(r, "factorize_s", f.wall);  // with factorize_min_s, factorize_max_s, factorize_reps
  set_spread(r, "factorize_cpu_s", f.cpu);
  set_spread(r, "solve_s", s.wall);
  set_spread(r, "solve_cpu_s", s.cpu);
  r.set("nnz_factor", double(ph.stats.nnz_factor), "count");
  r.set("factor_flops", ph.stats.flops > 0 ? ph.stats.flops : kNaN, "flop");
  r.set("gflops", ph.stats.flops > 0 && f.min() > 0 ? ph.stats.flops / f.min() / 1e9 : kNaN, "GFlop/s");  // fastest rep
  r.set("factor_bytes", double(ph.stats.factor_bytes), "bytes");
}

}  // namespace

ThesisSystem build_thesis_system(const std::string& mesh, const std::string& system) {
  SolverCell c;
  c.mesh = mesh;
  c.system = system;
  const Problem p = make_problem(c);
  const EnergyOperator op(p.Vn, p.mesh.F, p.adj, p.kind, EnergyOptions{});
  Timer tb;
  NormalSystem sys = build_normal_system(op, p.unk, Build::Structured);
  ThesisSystem t;
  t.build_s = tb.seconds();
  t.rhs = drag_rhs(p, sys);
  t.K.swap(sys.K);
  t.vertices = p.mesh.num_vertices();
  t.block = p.block;
  return t;
}

ThesisPattern build_thesis_pattern(const std::string& mesh, const std::string& system) {
  SolverCell c;
  c.mesh = mesh;
  c.system = system;
  const Problem p = make_problem(c);
  Timer tb;
  ThesisPattern t;
  t.pattern = interaction_pattern(p.adj, p.unk);  // the structured build's own (structured_build.cpp)
  t.build_s = tb.seconds();
  t.vertices = p.mesh.num_vertices();
  t.block = p.block;
  return t;
}

long long ThesisPattern::nnz_upper() const {
  if (pattern.colptr.empty()) return 0;
  const long long blocks = pattern.colptr.back(), diagonal = static_cast<long long>(pattern.colptr.size()) - 1;
  return block * block * (blocks - diagonal) + diagonal * block * (block + 1) / 2;
}

namespace {

// A registry backend on K (upper triangle): analyze, factorize (repeated), solve (repeated) of `rhs` into x, and
// one solve of b = K x_ref for the error.
CellResult measure_on(const SolverCell& c, const SystemFacts& f, const SpMat& K, int block, const DenseMat& rhs,
                      const DenseMat& xref, DenseMat& x) {
  CellResult r;
  add_system(r, f, K, int(rhs.cols()));
  const DenseMat bsyn = K.selfadjointView<Eigen::Upper>() * xref;
  SolverOptions so;
  so.block_size = block;
  so.ordering = c.ordering.rfind("vertex-", 0) == 0 ? "natural" : c.ordering;
  so.factor_dir = c.factor_dir;
  auto solver = make_solver(c.backend, so);
  Phases ph;
  const CpuTimer tac;
  Timer ta;
  solver->analyze(K);
  ph.analyze_s = f.order_s + ta.seconds();
  ph.analyze_cpu_s = f.order_cpu_s + tac.seconds();
  ph.factorize = repeat_timed(c.factor_reps, c.rep_seconds, [&] { solver->factorize(K); });
  ph.solve = repeat_timed(c.solve_reps, c.rep_seconds, [&] { solver->solve(rhs, x); });
  ph.stats = solver->stats();
  DenseMat xs;
  solver->solve(bsyn, xs);
  r.set("peak_rss_bytes", double(peak_rss_bytes()), "bytes");  // before anything below allocates
  add_phases(r, ph);
  // Iterative backends and the mixed-precision one (its refinement): iterations of the last solve.
  if (solver_info(c.backend).family == "iterative" || ph.stats.iterations > 0)
    r.set("iterations", ph.stats.iterations, "count");
  r.set_text("ordering_used", ph.stats.ordering_used);
  r.set("residual", rel_residual(K, x, rhs), "relative");
  r.set("residual_synthetic", rel_residual(K, xs, bsyn), "relative");
  r.set("error_exact", (xs - xref).norm() / xref.norm(), "relative");
  return r;
}

// The thesis edit's structured K for a registry backend.
CellResult measure_linear_solver(const SolverCell& c, const Problem& p, DenseMat& x) {
  const EnergyOperator op(p.Vn, p.mesh.F, p.adj, p.kind, EnergyOptions{});
  const CpuTimer tbc;
  Timer tb;
  const NormalSystem sys = build_normal_system(op, p.unk, Build::Structured);
  const SystemFacts f{double(p.mesh.num_vertices()), tb.seconds(), tbc.seconds(), p.order_s, p.order_cpu_s};
  return measure_on(c, f, sys.K, p.block, drag_rhs(p, sys), reference_solution(p, c.seed, sys.rhs_cols), x);
}

// The soft targets of the full drag in the solver layout, block * #soft x cols (least_squares_system's u).
DenseMat soft_targets(const Problem& p, int cols) {
  DenseMat u(Index(p.block * p.unk.soft_vertices.size()), cols);
  for (std::size_t k = 0; k < p.unk.soft_vertices.size(); ++k) {
    const Vec3 q = soft_target(p, p.unk.soft_vertices[k]);
    for (int c = 0; c < 3; ++c) at(u, p.block, int(k), c) = q(c);
  }
  return u;
}

// SPQR on the naive build's A: QR of A itself, A^T A never formed; accuracy on the normal equations.
CellResult measure_least_squares(const SolverCell& c, const Problem& p, DenseMat& x) {
  const EnergyOperator op(p.Vn, p.mesh.F, p.adj, p.kind, EnergyOptions{});
  const CpuTimer tbc;
  Timer tb;
  const NormalSystem sys = build_normal_system(op, p.unk, Build::Naive);
  // Soft constraints only: no hard vertices, so no A_h x_h term.
  const LeastSquaresSystem ls = least_squares_system(sys, p.unk, DenseMat(), soft_targets(p, sys.rhs_cols));
  const SpMat& A = ls.A;
  CellResult r;
  add_system(r, {double(p.mesh.num_vertices()), tb.seconds(), tbc.seconds(), p.order_s}, sys.K, sys.rhs_cols);
  r.set("matrix_bytes", double(sparse_bytes(A)), "bytes");
  const DenseMat rhs = drag_rhs(p, sys), xref = reference_solution(p, c.seed, sys.rhs_cols);
  const DenseMat bsyn = A * xref;

  SpqrLeastSquares qr(c.ordering);
  Phases ph;
  ph.analyze_s = p.order_s;
  ph.analyze_cpu_s = p.order_cpu_s;
  ph.factorize = repeat_timed(c.factor_reps, c.rep_seconds, [&] { qr.factorize(A); });
  ph.solve = repeat_timed(c.solve_reps, c.rep_seconds, [&] { qr.solve(ls.b, x); });
  ph.stats = qr.stats();
  DenseMat xs;
  qr.solve(bsyn, xs);
  r.set("peak_rss_bytes", double(peak_rss_bytes()), "bytes");
  add_phases(r, ph);
  r.set_text("ordering_used", ph.stats.ordering_used);
  r.set("residual", rel_residual(sys.K, x, rhs), "relative");
  r.set("residual_synthetic", rel_residual(sys.K, xs, DenseMat(A.transpose() * bsyn)), "relative");
  r.set("error_exact", (xs - xref).norm() / xref.norm(), "relative");
  return r;
}

}  // namespace

CellSpec SolverCell::to_spec() const {
  CellSpec s("solve");
  s.set("model", model).set("mesh", mesh).set("system", system).set("backend", backend).set("ordering", ordering);
  s.set("solve_reps", solve_reps).set("factor_reps", factor_reps).set("rep_seconds", rep_seconds);
  s.set("seed", static_cast<double>(seed));
  if (!positions.empty()) s.set("positions", positions);
  if (!factor_dir.empty()) s.set("factor_dir", factor_dir);
  if (!source.empty()) s.set("source", source);
  if (!options.empty()) s.set("options", options);
  if (!rhs.empty()) s.set("rhs", rhs);
  if (block != 1) s.set("block", block);
  if (threads > 0) s.set("threads", threads);
  return s;
}

SolverCell SolverCell::from_spec(const CellSpec& s) {
  s.check_keys({"model", "mesh", "system", "backend", "ordering", "solve_reps", "factor_reps", "rep_seconds", "seed",
                "positions", "factor_dir", "source", "options", "rhs", "block", "threads"});
  SolverCell c;
  c.mesh = s.get("mesh");
  c.model = s.get("model", c.mesh);
  c.system = s.get("system", c.system);
  c.backend = s.get("backend", c.backend);
  c.ordering = s.get("ordering", c.ordering);
  c.solve_reps = static_cast<int>(s.integer("solve_reps", c.solve_reps, 1, 1000000));
  c.factor_reps = static_cast<int>(s.integer("factor_reps", c.factor_reps, 1, 1000000));
  c.rep_seconds = s.real("rep_seconds", c.rep_seconds, 0, 1e6);
  c.seed = static_cast<unsigned>(s.integer("seed", c.seed, 0, 4294967295LL));
  c.positions = s.get("positions", "");
  c.factor_dir = s.get("factor_dir", "");
  c.source = s.get("source", "");
  if (!c.source.empty() && c.source != "edit" && c.source != "matrix")
    throw UsageError("source=" + c.source + ": not edit or matrix");
  c.options = s.get("options", "");
  c.rhs = s.get("rhs", "");
  c.block = static_cast<int>(s.integer("block", 1, 1, 64));
  c.threads = static_cast<int>(s.integer("threads", 0, 0, 4096));
  return c;
}

std::string SolverCell::key() const {
  return fmt::format("{}/{}/{}/{}{}", model, system, backend, ordering, threads > 0 ? fmt::format("/t{}", threads) : "");
}

std::string solver_family(const std::string& backend) {
  return backend == kLeastSquaresBackend ? "least-squares" : solver_info(backend).family;
}

std::vector<std::string> solver_orderings(const std::string& backend) {
  if (backend == kLeastSquaresBackend) return {"default", "colamd", "amd", "metis", "natural"};
  return solver_info(backend).orderings;
}

DeformOptions parse_option_items(const std::string& text) {
  DeformOptions o;
  std::vector<std::string> given;
  std::size_t at = 0;
  while (at < text.size()) {
    const std::size_t end = std::min(text.find(';', at), text.size()), eq = text.find('=', at);
    if (eq == std::string::npos || eq > end) throw UsageError("options=" + text + ": not key=value;key=value");
    const std::string key = text.substr(at, eq - at);
    set_deform_option(o, key, text.substr(eq + 1, end - eq - 1));
    given.push_back(key);
    at = end + 1;
  }
  return resolve_options(o, given);
}

std::string option_items_text(const DeformOptions& o) {
  std::string s;
  const std::vector<std::string>& groups = system_option_groups();  // the rest does not shape the system
  for (const auto& [k, v] : deform_option_items(o))
    if (std::count(groups.begin(), groups.end(), deform_option_def(k).group) > 0) s += (s.empty() ? "" : ";") + k + "=" + v;
  return s;
}

namespace {

// x_ref of a system without vertices: seeded, uniform in [-1, 1].
DenseMat random_solution(unsigned seed, Eigen::Index rows, Eigen::Index cols) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  DenseMat x(rows, cols);
  for (Eigen::Index i = 0; i < rows; ++i)
    for (Eigen::Index j = 0; j < cols; ++j) x(i, j) = uni(rng);
  return x;
}

// A solution as rows of three (zero-padded) for the parent's comparisons between cells.
Points as_rows_of_three(const DenseMat& x) {
  const Eigen::Index n = x.size();
  Points P = Points::Zero((n + 2) / 3, 3);
  for (Eigen::Index k = 0; k < n; ++k) P(k / 3, k % 3) = x(k % x.rows(), k / x.rows());
  return P;
}

// The edit's system `c.system` (source=edit) or the Matrix Market one (source=matrix).
CellResult measure_other_source(const SolverCell& c, DenseMat& x) {
  SystemFacts f;
  SpMat K;
  DenseMat rhs;
  int block = 1;
  if (c.source == "edit") {
    const EditCase ec = load_edit_case(c.mesh);
    f.vertices = ec.mesh.num_vertices();
    const CpuTimer tc;
    std::vector<EditSystem> systems = edit_systems(ec.mesh, ec.edit, parse_option_items(c.options));
    f.build_cpu_s = tc.seconds();
    auto it = std::find_if(systems.begin(), systems.end(), [&](const EditSystem& e) { return e.name == c.system; });
    if (it == systems.end()) throw UsageError(fmt::format("system={}: not one of this method's systems", c.system));
    f.build_s = it->build_s;
    K.swap(it->K);
    rhs = std::move(it->rhs);
    block = it->block;
  } else {
    Timer t;
    const CpuTimer tc;
    K = read_market_spd(c.mesh);
    block = c.block;
    if (K.rows() % block != 0) throw UsageError(fmt::format("block={}: {} rows are not whole blocks", block, K.rows()));
    if (!c.rhs.empty()) rhs = read_market_array(c.rhs, K.rows());
    f.build_s = t.seconds();  // reading the files
    f.build_cpu_s = tc.seconds();
  }
  const DenseMat xref = random_solution(c.seed, K.rows(), rhs.cols() > 0 ? rhs.cols() : 1);
  if (rhs.cols() == 0) rhs = K.selfadjointView<Eigen::Upper>() * xref;  // no right-hand side: the synthetic one
  return measure_on(c, f, K, block, rhs, xref, x);
}

// What the child's libraries actually use (the parent set the environment).
void add_threads_used(CellResult& r) {
  r.set("blas_threads_used", provenance().blas_threads, "count");
  r.set("own_threads_used", worker_threads(), "count");
  const char* omp = std::getenv("OMP_NUM_THREADS");
  r.set("omp_threads_used", omp && *omp ? std::atof(omp) : kNaN, "count");
}

}  // namespace

CellResult measure_solver_cell(const CellSpec& spec) {
  const SolverCell c = SolverCell::from_spec(spec);
  DenseMat x;
  CellResult r;
  if (!c.source.empty()) {
    if (c.backend == kLeastSquaresBackend) throw UsageError("backend=spqr: the thesis edit's cells only");
    r = measure_other_source(c, x);
    if (!c.positions.empty()) write_positions(c.positions, as_rows_of_three(x));
  } else {
    const Problem p = make_problem(c);
    r = c.backend == kLeastSquaresBackend ? measure_least_squares(c, p, x) : measure_linear_solver(c, p, x);
    if (c.ordering.rfind("vertex-", 0) == 0) r.set_text("ordering_used", c.ordering.substr(7) + "-vertex-graph");
    if (!c.positions.empty()) write_positions(c.positions, to_vertices(x, p));
  }
  add_threads_used(r);
  return r;
}

}  // namespace db::harness
