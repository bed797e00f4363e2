#include "methods/run_prediction.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <vector>

#include <fmt/format.h>

#include "core/child_process.h"
#include "core/csv.h"
#include "core/csv_reader.h"
#include "core/enum_text.h"
#include "core/timer.h"
#include "methods/deformer.h"
#include "methods/normalization.h"
#include "operators/energy_operator.h"
#include "solvers/base/error.h"
#include "solvers/base/resources.h"
#include "solvers/linear_solver.h"
#include "systems/lri_system.h"
#include "systems/normal_system.h"
#include "systems/vertex_ordering.h"

namespace db {
namespace {

// What a method holds per vertex besides the system and the factor: normalized positions, adjacency, operator
// weights, unknown numbering, per-frame right-hand sides and positions (order of magnitude of its arrays).
constexpr double kMethodBytesPerVertex = 400;
// A mesh's own bytes per vertex (positions, two faces of three indices), for --scale.
constexpr double kMeshBytesPerVertex = 48;
const double kNaN = std::numeric_limits<double>::quiet_NaN();

//! One system to factor: its block size and the rings of its vertex graph.
struct SystemShape {
  int block = 1, rings = 2;
};

//! The vertex graph's upper-triangular pattern as a matrix of ones (analyze reads the pattern only).
SpMat pattern_matrix(const InteractionPattern& pat, int n) {
  SpMat P(n, n);
  P.resizeNonZeros(static_cast<Eigen::Index>(pat.rows.size()));
  std::copy(pat.colptr.begin(), pat.colptr.end(), P.outerIndexPtr());
  std::copy(pat.rows.begin(), pat.rows.end(), P.innerIndexPtr());
  std::fill(P.valuePtr(), P.valuePtr() + pat.rows.size(), 1.0);
  return P;
}

//! The vertex ordering the run gives its structured build (LaplacianDeformer::build), "" when the backend orders.
std::string vertex_ordering_of(const DeformOptions& o, int block, bool exact) {
  const SolverInfo info = solver_info(o.solver);
  const bool takes_natural =
      std::find(info.orderings.begin(), info.orderings.end(), "natural") != info.orderings.end();
  const std::string& ord = o.solver_options.ordering;
  if (o.build != Build::Structured || ord == "natural" || !takes_natural || info.family == "iterative") return "";
  return !exact ? "amd" : ord == "default" ? default_vertex_ordering(block) : ord;
}

}  // namespace

// Mirrors LaplacianDeformer::build: a structured build orders the vertex graph itself and hands the backend a
// matrix in that order (natural); other builds, and backends that take no natural ordering, order in the backend.
// `pat`: the vertex graph, in the vertex order when `ordered`.
FactorCount count_factor(const InteractionPattern& pat, int nu_int, bool ordered, int block, const DeformOptions& o,
                         bool exact) {
  FactorCount f;
  const SolverInfo info = solver_info(o.solver);
  const double b = block, nu = nu_int;
  Timer t;
  SolverOptions so = o.solver_options;
  so.factor_dir.clear();  // a pattern analysis: never out of core (a fallback backend may not keep a factor on disk)
  if (ordered) so.ordering = "natural";
  else if (!exact) so.ordering = "default";
  const double upper = static_cast<double>(pat.rows.size());
  f.nnz_matrix = b * b * (upper - nu) + b * (b + 1) / 2 * nu;
  if (info.family == "iterative") {  // no factor; the incomplete Cholesky keeps K's pattern
    f.nnz = o.solver == "cg_ichol" ? f.nnz_matrix : 0;
    f.workspace = 12 * (2 * f.nnz_matrix - b * nu);  // CG runs on a full (both triangles) copy of K
    f.backend = o.solver;
    f.seconds = t.seconds();
    f.basis = fmt::format("{}: no factor analysis ({} nonzeros of K)", o.solver, f.nnz_matrix);
    return f;
  }
  // Backends that count nothing before they factorize are counted by CHOLMOD's supernodal analysis instead.
  const SpMat P = pattern_matrix(pat, nu_int);
  std::string used = info.family == "dense" ? "cholmod_supernodal" : o.solver;
  if (so.ordering != "natural" && so.ordering != "default") {
    const auto& acc = solver_info(used).orderings;
    if (std::find(acc.begin(), acc.end(), so.ordering) == acc.end()) so.ordering = "default";
  }
  auto solver = make_solver(used, so);
  solver->analyze(P);
  FactorStats st = solver->stats();
  if (st.nnz_factor == 0) {  // timed alone: the first backend's analysis (MUMPS: its MPI start) is not the work
    t = Timer();
    used = "cholmod_supernodal";
    if (so.ordering != "natural") so.ordering = "default";
    solver = make_solver(used, so);
    solver->analyze(P);
    st = solver->stats();
  }
  f.seconds = t.seconds();
  f.backend = used;
  const double vnnz = static_cast<double>(st.nnz_factor);
  f.nnz = b * b * (vnnz - nu) + b * (b + 1) / 2 * nu;
  f.flops = b * b * b * std::max(0.0, st.flops);
  f.workspace = b * b * static_cast<double>(st.workspace_bytes);
  f.basis = fmt::format("{} analysis of the {}-vertex graph ({}), blocks of {}", used, nu_int,
                        ordered ? "in the vertex order" : st.ordering_used, block);
  return f;
}

double stencil_flops(const Adjacency& adj, int nv, int b) {
  double s = 0;
  for (int i = 0; i < nv; ++i) s += std::pow(adj.degree(i) + 1.0, 2);
  return 2.0 * b * b * b * s;
}

namespace {

//! Counts at `scale` times the vertices of a surface under nested dissection.
void scale_counts(RunPrediction& p, double scale, double n) {
  if (scale == 1) return;
  const double nnz_growth = scale * (1 + std::log(scale) / std::log(std::max(n, 2.0)));
  p.n *= scale;
  p.nnz_matrix *= scale;
  p.build_bytes *= scale;
  p.build_flops *= scale;
  p.factor_nnz *= nnz_growth;
  p.factor_bytes *= nnz_growth;
  p.factor_flops *= std::pow(scale, 1.5);
  p.workspace_bytes *= scale;
  p.analysis_s *= scale;
}

void dense_counts(RunPrediction& p, double n) {
  p.factor_nnz = n * (n + 1) / 2;
  p.factor_flops = n * n * n / 3;
  p.factor_bytes = 0;  // the caller counts the factorization's own n x n matrix
  p.basis = "dense: n^2 doubles, n^3 / 3 flops";
}

std::vector<SystemShape> shapes(const DeformOptions& o) {
  if (o.method == Method::Lri) return {{3, 1}, {1, 1}};
  std::vector<SystemShape> s{{o.method == Method::Tf ? 3 : 1, 2}};
  if (o.method == Method::Tf && o.tf_scale == TfScale::Normalized) s.push_back({1, 2});
  return s;
}

void apply_rates(RunPrediction& p, const std::optional<BackendRates>& r) {
  const double factor_bytes = p.factor_bytes + p.workspace_bytes;
  p.peak_bytes = p.base_bytes + p.build_bytes + (r ? r->peak_fixed_bytes + factor_bytes * r->peak_per_factor
                                                   : factor_bytes);
  if (!r) {
    p.build_s = p.analyze_s = p.factorize_s = p.init_s = kNaN;
    return;
  }
  p.build_s = r->build.seconds(p.build_flops);
  p.analyze_s = r->analyze.seconds(p.analysis_s);
  p.factorize_s = r->factorize.seconds(p.factor_flops > 0 ? p.factor_flops : p.nnz_matrix);
  if (r->peak_flop_rate > 0) p.factorize_s = std::max(p.factorize_s, p.factor_flops / r->peak_flop_rate);
  p.init_s = p.build_s + p.analyze_s + p.factorize_s;
}

// The calibration file's columns of one BackendRates, in order (the phases as PhaseRate::text).
constexpr const char* kPhaseColumns[] = {"build", "analyze", "factorize"};
constexpr const char* kBytesColumns[] = {"peak_per_factor", "peak_fixed_bytes"};

std::vector<PhaseRate*> phases(BackendRates& r) { return {&r.build, &r.analyze, &r.factorize}; }
std::vector<double*> bytes_fields(BackendRates& r) { return {&r.peak_per_factor, &r.peak_fixed_bytes}; }

//! A non-negative finite number, the whole of `text`. \throw InputError naming `what`.
double rate_number(const std::string& text, const std::string& what) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v) || v < 0)
    throw InputError(fmt::format("{} = {} is not a rate", what, text));
  return v;
}

}  // namespace

double PhaseRate::seconds(double units) const {
  if (points.empty() || units <= 0) return 0;
  if (points.size() == 1) return points[0].second * units / points[0].first;
  // the segment [i - 1, i] holding `units`, else the end segment on its side
  std::size_t i = 1;
  while (i + 1 < points.size() && units > points[i].first) ++i;
  const auto [u0, s0] = points[i - 1];
  const auto [u1, s1] = points[i];
  double k = std::clamp(std::log(s1 / s0) / std::log(u1 / u0), kMinExponent, kMaxExponent);
  if (units > u1) k = std::min(k, 1.0);
  return s1 * std::pow(units / u1, k);
}

PhaseRate PhaseRate::fit(std::vector<std::pair<double, double>> pts) {
  PhaseRate r;
  std::stable_sort(pts.begin(), pts.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& p : pts) {
    if (!(p.first > 0 && p.second > 0 && std::isfinite(p.first) && std::isfinite(p.second))) continue;
    if (!r.points.empty() && r.points.back().first == p.first) r.points.back() = p;
    else r.points.push_back(p);
  }
  return r;
}

std::string PhaseRate::text() const {
  std::vector<std::string> parts;
  for (const auto& [u, sec] : points) parts.push_back(num(u) + ":" + num(sec));
  return fmt::format("{}", fmt::join(parts, ";"));
}

PhaseRate PhaseRate::parse(const std::string& text) {
  std::vector<std::pair<double, double>> pts;
  std::size_t at = 0;
  while (at < text.size()) {
    const std::size_t end = std::min(text.find(';', at), text.size()), colon = text.find(':', at);
    if (colon == std::string::npos || colon > end) throw InputError(fmt::format("'{}' is not units:seconds", text));
    pts.emplace_back(rate_number(text.substr(at, colon - at), "units"),
                     rate_number(text.substr(colon + 1, end - colon - 1), "seconds"));
    at = end + 1;
  }
  PhaseRate r = fit(pts);
  if (!text.empty() && text.back() == ';') throw InputError(fmt::format("'{}' ends with ';'", text));
  if (r.points.size() != pts.size()) throw InputError(fmt::format("'{}': points not positive and distinct", text));
  return r;
}

std::string MachineCalibration::key(const std::string& backend, Build build, Method method,
                                    const std::string& ordering) {
  const std::string k = fmt::format("{}/{}/{}", backend, to_string(build), to_string(method));
  return ordering.empty() || ordering == "default" ? k : k + "/" + ordering;
}

std::optional<BackendRates> MachineCalibration::find(const std::string& backend, Build build, Method method,
                                                     const std::string& ordering) const {
  const Method m = method == Method::Lri ? Method::Tf : method;
  const auto base = rates.find(key(backend, build, m)), own = rates.find(key(backend, build, m, ordering));
  if (base == rates.end() && own == rates.end()) return std::nullopt;
  BackendRates r = base != rates.end() ? base->second : own->second;
  if (own != rates.end()) {
    r.build = own->second.build;
    r.analyze = own->second.analyze;
  }
  r.peak_flop_rate = dense_flop_rate();
  return r;
}

double MachineCalibration::dense_flop_rate() const {
  double best = 0;
  for (const auto& [k, r] : rates)
    if (k.rfind("lapack_potrf/", 0) == 0)
      for (const auto& [flops, seconds] : r.factorize.points) best = std::max(best, flops / seconds);
  return best;
}

void MachineCalibration::save(const std::string& path) const {
  CsvTable t;
  for (const auto& [k, r] : rates) {
    CsvTable::Row row{{"key", k}};
    BackendRates copy = r;
    const std::vector<PhaseRate*> ph = phases(copy);
    for (std::size_t i = 0; i < ph.size(); ++i) row.emplace_back(kPhaseColumns[i], ph[i]->text());
    const std::vector<double*> by = bytes_fields(copy);
    for (std::size_t i = 0; i < by.size(); ++i) row.emplace_back(kBytesColumns[i], num(*by[i]));
    row.emplace_back("calibration", provenance);
    t.add(std::move(row));
  }
  t.write(path);
}

MachineCalibration MachineCalibration::load(const std::string& path) {
  MachineCalibration c;
  if (!std::ifstream(path)) return c;
  for (const CsvRow& row : read_csv(path)) {
    auto field = [&](const char* k) -> const std::string& {
      const auto it = row.find(k);
      if (it == row.end()) throw InputError(fmt::format("a row without {} (a file of an older layout?)", k));
      return it->second;
    };
    BackendRates r;
    std::string key;
    try {
      key = field("key");
      const std::vector<PhaseRate*> ph = phases(r);
      for (std::size_t i = 0; i < ph.size(); ++i) *ph[i] = PhaseRate::parse(field(kPhaseColumns[i]));
      const std::vector<double*> by = bytes_fields(r);
      for (std::size_t i = 0; i < by.size(); ++i) *by[i] = rate_number(field(kBytesColumns[i]), kBytesColumns[i]);
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}: {}{}", path, key.empty() ? "" : key + ": ", e.what()));
    }
    c.rates[key] = r;
    c.provenance = row.count("calibration") ? row.at("calibration") : "";
  }
  return c;
}

RunPredictor::RunPredictor(const Mesh& mesh, const Edit& edit)
    : mesh_(mesh), edit_(edit), adj_(vertex_adjacency(mesh)), rss_(static_cast<double>(current_rss_bytes())) {}

RunPredictor::~RunPredictor() = default;

const RunPredictor::Graph& RunPredictor::graph(const DeformOptions& o, int rings, const std::string& ordering) {
  const std::string key = fmt::format("{}|{}|{}|{}", to_string(o.constraints), o.soft_weight, rings, ordering);
  auto it = graphs_.find(key);
  if (it != graphs_.end()) return *it->second;
  auto g = std::make_unique<Graph>();
  const auto kinds = classify(edit_, o.constraints);
  check_every_component_anchored(adj_, kinds);
  g->unk = make_unknowns(kinds, o.soft_weight);
  Timer t;
  g->pattern = interaction_pattern(adj_, g->unk, rings);
  if (!ordering.empty()) {
    // As the run orders (the adjacency for METIS's guided splits, where the pattern is its 2-ring one).
    order_unknowns(g->pattern, g->unk, ordering, rings == 2 ? &adj_ : nullptr);
    g->seconds = t.seconds();  // what the run counts as its ordering: the pattern built, then ordered
    g->pattern = interaction_pattern(adj_, g->unk, rings);
  }
  return *graphs_.emplace(key, std::move(g)).first->second;
}

double RunPredictor::build_bytes(const DeformOptions& o, const Unknowns& unk) const {
  if (o.method == Method::Lri) {
    double bytes = 0;
    for (const SystemShape& s : shapes(o)) bytes += predict_edge_system_bytes(adj_, unk, s.block, o.build);
    return bytes;
  }
  const Points Vn = (o.normalize ? Normalization::fit(mesh_.V) : Normalization::identity()).apply(mesh_.V);
  EnergyOptions eo;
  eo.weights = o.weights;
  eo.tf_translation = o.tf_translation;
  const EnergyOperator op(Vn, mesh_.F, adj_, o.method == Method::Tf ? EnergyKind::Tf : EnergyKind::Lap, eo);
  return static_cast<double>(predict_build_bytes(op, unk, o.build));
}

RunPrediction RunPredictor::predict(const DeformOptions& options, const MachineCalibration& calibration,
                                    double scale, bool exact_ordering) {
  const DeformOptions o = resolve_options(options);
  RunPrediction p;
  const double nv = mesh_.num_vertices();
  p.base_bytes = rss_ + (scale - 1) * kMeshBytesPerVertex * nv + scale * kMethodBytesPerVertex * nv;
  double nu = 0;
  for (const SystemShape& s : shapes(o)) {
    const std::string ordering = vertex_ordering_of(o, s.block, exact_ordering);
    const Graph& g = graph(o, s.rings, ordering);
    nu = g.unk.num_unknowns();
    if (p.n == 0) p.build_bytes = build_bytes(o, g.unk);
    const double n = s.block * nu;
    p.n += n;
    // The dense build multiplies the dense rows out (A^T A: rows x n^2); the sparse ones row block by row block.
    const double rows = static_cast<double>(s.block) * nv;
    p.build_flops += o.build == Build::Dense ? rows * n * n : stencil_flops(adj_, mesh_.num_vertices(), s.block);
    if (o.build == Build::Dense || solver_info(o.solver).family == "dense") {
      RunPrediction d;
      dense_counts(d, n);
      p.nnz_matrix += d.factor_nnz;
      p.factor_nnz += d.factor_nnz;
      p.factor_flops += d.factor_flops;
      // The factorization's own n x n matrix: a sparse build hands the dense backend K to copy into it; the dense
      // build's prediction holds it among the build's matrices (predict_build_bytes), moved here so that the
      // calibrated ratio applies to it.
      p.factor_bytes += 8 * n * n;
      if (o.build == Build::Dense && p.n == n) p.build_bytes = std::max(0.0, p.build_bytes - 8 * n * n);
      p.basis = d.basis;
      continue;
    }
    const FactorCount f = count_factor(g.pattern, g.unk.num_unknowns(), !ordering.empty(), s.block, o, exact_ordering);
    p.nnz_matrix += f.nnz_matrix;
    p.factor_nnz += f.nnz;
    p.factor_flops += f.flops;
    const double value_bytes = o.precision == Precision::Mixed ? 4 : 8;
    p.factor_bytes += (value_bytes + 4) * f.nnz;
    p.workspace_bytes += f.workspace;
    p.analysis_s += f.seconds + g.seconds;
    p.basis += (p.basis.empty() ? "" : "; ") + f.basis;
  }
  scale_counts(p, scale, nu);
  apply_rates(p, calibration.find(o.solver, o.build, o.method, o.solver_options.ordering));
  return p;
}

RunPrediction predict_run(const Mesh& mesh, const Edit& edit, const DeformOptions& options,
                          const MachineCalibration& calibration, double scale, bool exact_ordering) {
  return RunPredictor(mesh, edit).predict(options, calibration, scale, exact_ordering);
}

std::string calibration_path() {
  if (const char* env = std::getenv("DEFORMBENCH_CALIBRATION"); env && *env) return env;
  return (std::filesystem::path(self_executable()).parent_path() / "machine_calibration.csv").string();
}

std::size_t available_memory_bytes() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  std::size_t kb = 0;
  std::string unit;
  while (in >> key >> kb >> unit)
    if (key == "MemAvailable:") return kb * 1024;
  return 0;
}

}  // namespace db
