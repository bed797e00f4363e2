// deformbench advise EDIT [deform's method, constraint and weight options] [--frames N] [--threads T]
//                    [--budget-mb M] [--csv F] [--md F] [--backends B,...] [--timeout-s S] [--predict-only]
//                    [--scale K] [--calibrate]
// Which backend to use for this edit on this machine: each applicable backend (the fill-reducing orderings that
// matter for the two supernodal ones) deformed in a fresh child process (`deformbench deform --csv`) under a time
// limit and the memory budget, after a prediction (methods/run_prediction.h) that skips the ones over budget; one
// ranked table, a verdict line, CSV and Markdown. --calibrate measures the rates the predictions use on this
// machine (a generated plane deformed with each backend) and keeps them beside the binary.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "commands.h"
#include "core/child_process.h"
#include "core/cli.h"
#include "core/csv.h"
#include "core/csv_reader.h"
#include "core/provenance.h"
#include "core/scratch_prefix.h"
#include "edit/edit_io.h"
#include "mesh/mesh_io.h"
#include "mesh/procedural.h"
#include "methods/deform_options.h"
#include "methods/deform_option_flags.h"
#include "methods/run_prediction.h"
#include "methods/scaled_edit.h"
#include "solvers/base/atomic_file.h"
#include "solvers/base/error.h"
#include "solvers/linear_solver.h"

namespace db::commands {
namespace {

namespace fs = std::filesystem;
const double kNaN = std::numeric_limits<double>::quiet_NaN();
// The reference every row's error is measured against: the double factor refined to the exact solution.
const char* const kReference = "multifrontal_refined";

struct AdviseArgs {
  std::string edit, csv, md, backends;
  long long frames = 5;
  int threads = 0;
  double budget_mb = 0, timeout_s = 600, scale = 1;
  bool predict_only = false, calibrate = false, quick = false;
  std::map<std::string, std::string> values;  // deform option key -> text, as given
};

//! One backend (and ordering) on the edit: what was predicted and what its children measured.
struct Row {
  std::string backend, ordering, status = "ok";
  RunPrediction predicted;
  double init_s = kNaN, frame_s = kNaN, handle_frame_s = kNaN, peak = kNaN, factor = kNaN, error = kNaN;
  double nnz_factor = kNaN, flops = kNaN, build_s = kNaN, analyze_s = kNaN, factorize_s = kNaN;
  bool ok() const { return status == "ok"; }
  std::string label() const { return ordering == "default" ? backend : backend + "/" + ordering; }
  double total(long long frames) const { return init_s + static_cast<double>(frames) * frame_s; }
};

// The deform options of the command line, as given, and their flags and values for the children.
struct GivenOptions {
  DeformOptions options;
  std::vector<std::string> argv;
};

GivenOptions given_options(const CLI::App& app, const AdviseArgs& a) {
  GivenOptions g{deform_options_given(app, a.values), {}};
  for (const std::string& key : deform_option_keys_given(app, a.values)) {
    const DeformOptionDef& def = deform_option_def(key);
    g.argv.push_back(def.flag);
    if (!def.is_switch) g.argv.push_back(a.values.at(key));
  }
  return g;
}

// The backends worth a child for these options, each sparse Cholesky that orders the vertex graph with both
// orderings that matter on meshes (AMD and METIS), the others with their default.
std::vector<Row> candidates(const DeformOptions& o, const std::string& only) {
  std::vector<Row> rows;
  auto add = [&](const std::string& b, const std::string& ord) {
    if (!only.empty() && ("," + only + ",").find("," + b + ",") == std::string::npos) return;
    Row r;
    r.backend = b;
    r.ordering = ord;
    rows.push_back(r);
  };
  if (o.build == Build::Dense) {
    for (const char* b : {"dense_llt", "lapack_potrf"}) add(b, "default");
    return rows;
  }
  if (o.precision == Precision::Mixed) {
    add("multifrontal_mixed", "default");
    return rows;
  }
  for (const char* b : {"multifrontal", "cholmod_supernodal"})
    for (const char* ord : {"metis", "amd"}) add(b, ord);
  for (const char* b : {"cholmod_simplicial_ldlt", "eigen_simplicial_llt", "eigen_simplicial_ldlt", "umfpack",
                        "eigen_sparse_lu", "mumps", "multifrontal_mixed", "cg_ichol", "cg_jacobi", "dense_llt",
                        "lapack_potrf"})
    if (o.method != Method::Lri || solver_info(b).family != "iterative") add(b, "default");
  return rows;
}

//! The options of one row's children (the ones given, the row's backend and ordering).
DeformOptions row_options(DeformOptions o, const Row& r) {
  o.solver = r.backend;
  o.solver_options.ordering = r.ordering;
  if (r.backend == "multifrontal_mixed") o.precision = Precision::Mixed;
  return resolve_options(o);
}

struct Session {
  const AdviseArgs& args;
  GivenOptions given;
  EditCase ec;
  MachineCalibration calibration;
  std::unique_ptr<RunPredictor> predictor;  // of `ec` (of `scaled` with --scale), made once it is loaded
  std::unique_ptr<ScaledEdit> scaled;       // --scale: the mesh subdivided to about K times its vertices
  std::size_t budget = 0;
  std::unique_ptr<ScratchPrefix> scratch;  // the children's outputs
  Points reference;
};

//! Runs `deform` in a child with the row's backend; returns its record (empty on failure, `why` set).
CsvRow run_deform_child(const Session& s, const Row& r, const std::string& frame_mode, std::string& why,
                        std::string* mesh_out = nullptr) {
  const std::string stem = s.scratch->path(fmt::format("{}-{}-{}", r.backend, r.ordering, frame_mode));
  std::vector<std::string> argv = {self_executable(), "deform", s.args.edit};
  argv.insert(argv.end(), s.given.argv.begin(), s.given.argv.end());
  argv.insert(argv.end(), {"--solver", r.backend, "--frames", std::to_string(s.args.frames), "--frame-mode",
                           frame_mode, "--out", stem + ".off", "--csv", stem + ".csv", "--memory-budget-mb",
                           std::to_string(std::max<std::size_t>(1, s.budget / 1000000))});
  if (r.ordering != "default") argv.insert(argv.end(), {"--ordering", r.ordering});
  if (r.backend == "multifrontal_mixed" && s.given.options.precision != Precision::Mixed)
    argv.insert(argv.end(), {"--precision", "mixed"});
  const ChildRun c = run_child(argv, s.args.timeout_s);
  if (!c.ok()) {
    why = c.timed_out ? c.describe() : c.describe() + ": " + c.stderr_tail(160);
    if (c.exit_code == 4) why = "over budget: " + c.stderr_tail(160);
    return {};
  }
  if (mesh_out) *mesh_out = stem + ".off";
  return read_csv(stem + ".csv").at(0);
}

double field(const CsvRow& row, const std::string& key) {
  const auto it = row.find(key);
  return it == row.end() || it->second.empty() ? kNaN : std::stod(it->second);
}

void measure(const Session& s, Row& r) {
  std::string why, mesh;
  const CsvRow full = run_deform_child(s, r, "full", why, &mesh);
  if (full.empty()) {
    r.status = why;
    return;
  }
  r.init_s = field(full, "init_s");
  r.frame_s = field(full, "frame_s");
  r.peak = field(full, "peak_rss_bytes");
  r.factor = field(full, "factor_bytes");
  r.nnz_factor = field(full, "nnz_factor");
  r.flops = field(full, "factor_flops");
  r.build_s = field(full, "build_s");
  r.analyze_s = field(full, "analyze_s");
  r.factorize_s = field(full, "factorize_s");
  if (s.reference.rows() > 0)
    r.error = (read_mesh(mesh).V - s.reference).cwiseAbs().maxCoeff() / bbox_diagonal(s.ec.mesh.V);
  if (s.args.quick) return;
  const CsvRow handle = run_deform_child(s, r, "handle", why);
  r.handle_frame_s = handle.empty() ? kNaN : field(handle, "frame_s");
}

std::string mb(double bytes) { return std::isnan(bytes) ? "-" : fmt::format("{:.1f}", bytes / 1e6); }
std::string sec(double s) { return std::isnan(s) ? "-" : fmt::format("{:.3g}", s); }

//! Predicts the row; sets the status of one predicted over the budget or the time limit.
void predict(const Session& s, Row& r) {
  const DeformOptions o = row_options(s.given.options, r);
  r.predicted = s.predictor->predict(o, s.calibration, s.scaled ? s.scaled->residual : 1, true);
  if (r.predicted.peak_bytes > static_cast<double>(s.budget)) r.status = "predicted over budget";
  else if (r.predicted.init_s > s.args.timeout_s) r.status = "predicted over time";
  else if (std::isnan(r.predicted.init_s) && solver_info(r.backend).family == "dense" && r.predicted.n > 20000)
    r.status = "predicted over time";  // uncalibrated: n^3 / 3 flops at n > 20000 take hours
}

void rank_rows(std::vector<Row>& rows, long long frames) {
  std::stable_sort(rows.begin(), rows.end(), [&](const Row& a, const Row& b) {
    if (a.ok() != b.ok()) return a.ok();
    return a.ok() && a.total(frames) < b.total(frames);
  });
}

// "use X; Y when memory is short; Z for many frames" from the ranked rows.
std::string verdict(const std::vector<Row>& rows, long long frames) {
  std::vector<const Row*> ok;
  for (const Row& r : rows)
    if (r.ok()) ok.push_back(&r);
  if (ok.empty()) return "verdict: no backend finished on this edit (see the status column)";
  const Row& best = *ok.front();
  std::string v = fmt::format("verdict: use {} (init {} s + {} frames of {} s)", best.label(), sec(best.init_s),
                              frames, sec(best.frame_s));
  const Row* small = *std::min_element(ok.begin(), ok.end(), [](auto* a, auto* b) { return a->peak < b->peak; });
  if (small != &best)
    v += fmt::format("; {} when memory is short (peak {} MB against {} MB)", small->label(), mb(small->peak),
                     mb(best.peak));
  const Row* drag = *std::min_element(ok.begin(), ok.end(), [](auto* a, auto* b) {
    return !std::isnan(a->handle_frame_s) && (std::isnan(b->handle_frame_s) || a->handle_frame_s < b->handle_frame_s);
  });
  if (!std::isnan(drag->handle_frame_s) && drag != &best)
    v += fmt::format("; {} for long interactive drags (handle frames of {} s)", drag->label(), sec(drag->handle_frame_s));
  return v;
}

std::vector<std::string> table_header(bool predict_only) {
  if (predict_only)
    return {"rank", "backend", "status", "pred. init s", "pred. peak MB", "pred. factor MB", "nnz(L)", "GFlop"};
  return {"rank", "backend", "status", "init s", "frame s", "handle frame s", "peak RSS MB", "factor MB",
          "error vs refined", "pred. init s", "pred. peak MB"};
}

std::vector<std::string> table_row(const Row& r, std::size_t rank, bool predict_only) {
  const RunPrediction& p = r.predicted;
  if (predict_only)
    return {std::to_string(rank), r.label(), r.status, sec(p.init_s), mb(p.peak_bytes),
            mb(p.factor_bytes + p.workspace_bytes), fmt::format("{:.3g}", p.factor_nnz),
            fmt::format("{:.3g}", p.factor_flops / 1e9)};
  return {std::to_string(rank), r.label(), r.status, sec(r.init_s), sec(r.frame_s), sec(r.handle_frame_s), mb(r.peak),
          mb(r.factor), std::isnan(r.error) ? "-" : fmt::format("{:.2e}", r.error), sec(p.init_s), mb(p.peak_bytes)};
}

std::string markdown(const std::vector<Row>& rows, bool predict_only) {
  const auto head = table_header(predict_only);
  std::string out = "| " + fmt::format("{}", fmt::join(head, " | ")) + " |\n|";
  for (std::size_t i = 0; i < head.size(); ++i) out += "---|";
  out += "\n";
  for (std::size_t i = 0; i < rows.size(); ++i)
    out += "| " + fmt::format("{}", fmt::join(table_row(rows[i], i + 1, predict_only), " | ")) + " |\n";
  return out;
}

CsvTable csv(const Session& s, const std::vector<Row>& rows) {
  CsvTable t;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    const RunPrediction& p = r.predicted;
    t.add({{"rank", std::to_string(i + 1)}, {"mesh", s.ec.mesh.name}, {"edit", s.ec.edit.name},
           {"method", to_string(s.given.options.method)}, {"constraints", to_string(s.given.options.constraints)},
           {"weights", to_string(s.given.options.weights)}, {"build", to_string(s.given.options.build)},
           {"vertices", std::to_string(s.ec.mesh.num_vertices())}, {"backend", r.backend}, {"ordering", r.ordering},
           {"status", r.status}, {"frames", std::to_string(s.args.frames)}, {"init_s", num(r.init_s)},
           {"frame_s", num(r.frame_s)}, {"handle_frame_s", num(r.handle_frame_s)}, {"peak_rss_bytes", num(r.peak)},
           {"factor_bytes", num(r.factor)}, {"error_vs_refined", num(r.error)}, {"nnz_factor", num(r.nnz_factor)},
           {"factor_flops", num(r.flops)}, {"build_s", num(r.build_s)}, {"analyze_s", num(r.analyze_s)},
           {"factorize_s", num(r.factorize_s)}, {"predicted_peak_bytes", num(p.peak_bytes)},
           {"predicted_base_bytes", num(p.base_bytes)}, {"predicted_build_bytes", num(p.build_bytes)},
           {"predicted_factor_bytes", num(p.factor_bytes + p.workspace_bytes)},
           {"predicted_nnz_factor", num(p.factor_nnz)}, {"predicted_factor_flops", num(p.factor_flops)},
           {"predicted_init_s", num(p.init_s)}, {"scale", num(s.args.scale)},
           {"budget_bytes", std::to_string(s.budget)}, {"calibration", s.calibration.provenance}});
  }
  return t;
}

void print_table(const std::vector<Row>& rows, bool predict_only) {
  const auto head = table_header(predict_only);
  std::vector<std::vector<std::string>> cells{head};
  for (std::size_t i = 0; i < rows.size(); ++i) cells.push_back(table_row(rows[i], i + 1, predict_only));
  std::vector<std::size_t> w(head.size(), 0);
  for (const auto& c : cells)
    for (std::size_t j = 0; j < c.size(); ++j) w[j] = std::max(w[j], c[j].size());
  for (const auto& c : cells) {
    std::string line;
    for (std::size_t j = 0; j < c.size(); ++j) line += fmt::format("{:<{}}  ", c[j], w[j]);
    fmt::print("{}\n", line);
  }
}

//! The reference solution (the refined double factor) the rows' errors are measured against.
void reference(Session& s) {
  Row r;
  r.backend = kReference;
  r.ordering = "default";
  std::string why, mesh;
  if (run_deform_child(s, r, "full", why, &mesh).empty())
    fmt::print(stderr, "[advise] no reference solution ({}): the error column stays empty\n", why);
  else
    s.reference = read_mesh(mesh).V;
}

//! --scale's mesh: the edit's subdivided (scale_edit), or where it cannot be (not an oriented 2-manifold) the edit's
//! own with all of the scale left to the growth law, said on stderr.
std::unique_ptr<ScaledEdit> scaled_for_prediction(const EditCase& ec, double scale) {
  // The subdivision and its analyses take minutes near the cap: say what is coming before the wait.
  const int levels = scale_levels(ec.mesh.num_vertices(), scale);
  if (levels > 0)
    fmt::print(stderr, "[advise] --scale {}: Loop-subdividing the mesh {} time(s), to about {:.0f} vertices, then "
               "analysing it\n", scale, levels, ec.mesh.num_vertices() * std::pow(4.0, levels));
  try {
    return std::make_unique<ScaledEdit>(scale_edit(ec.mesh, ec.edit, scale));
  } catch (const InputError& e) {
    fmt::print(stderr, "[advise] --scale: the mesh cannot be subdivided ({}): the growth law predicts all of it\n",
               e.what());
    return std::make_unique<ScaledEdit>(ScaledEdit{ec.mesh, ec.edit, 0, scale});
  }
}

std::string scale_note(const ScaledEdit& sc, double scale) {
  return fmt::format(", predicted at {}x the vertices (the mesh Loop-subdivided {} time(s): {} vertices{})", scale,
                     sc.levels, sc.mesh.num_vertices(),
                     sc.residual != 1 ? fmt::format("; x{:.3g} more by the growth law", sc.residual) : "");
}

void progress(const Row& r, std::size_t i, std::size_t n) {
  const RunPrediction& p = r.predicted;
  if (!r.ok() || std::isnan(r.init_s))
    fmt::print(stderr, "[advise] {}/{} {}: {} (predicted peak {} MB, init {} s)\n", i, n, r.label(), r.status,
               mb(p.peak_bytes), sec(p.init_s));
  else
    fmt::print(stderr, "[advise] {}/{} {}: init {} s, frame {} s, peak {} MB (predicted {} s, {} MB)\n", i, n,
               r.label(), sec(r.init_s), sec(r.frame_s), mb(r.peak), sec(p.init_s), mb(p.peak_bytes));
}

//! The rows, predicted and (unless --predict-only) measured, in the order of `candidates`.
std::vector<Row> evaluate(Session& s) {
  std::vector<Row> rows = candidates(s.given.options, s.args.backends);
  if (rows.empty()) throw UsageError(fmt::format("--backends {}: none of them applies here", s.args.backends));
  for (Row& r : rows) predict(s, r);
  if (s.args.predict_only) {
    for (Row& r : rows)
      if (r.ok()) r.status = "predicted";
    return rows;
  }
  if (!s.args.quick) reference(s);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (rows[i].ok()) measure(s, rows[i]);
    progress(rows[i], i + 1, rows.size());
  }
  return rows;
}

void set_threads(int threads) {
  if (threads <= 0) return;
  const std::string t = std::to_string(threads);
  for (const char* var : {"OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "DEFORMBENCH_THREADS"}) ::setenv(var, t.c_str(), 1);
}

int run_advise(const CLI::App& app, const AdviseArgs& a);

}  // namespace

//! --calibrate (apps/commands/advise_calibrate.cpp).
int calibrate_machine(const std::string& path, double timeout_s);

namespace {

int run_advise(const CLI::App& app, const AdviseArgs& a) {
  set_threads(a.threads);
  if (a.calibrate) return calibrate_machine(calibration_path(), a.timeout_s);
  Session s{a, given_options(app, a), {}, {}, nullptr, nullptr, 0, {}, {}};
  const std::vector<std::string> inputs = edit_case_files(a.edit);
  const std::string md = !a.md.empty() ? a.md : a.csv.empty() ? "" : fs::path(a.csv).replace_extension(".md").string();
  if (!a.csv.empty()) cli::check_output("--csv", a.csv, {".csv"}, inputs);
  if (!md.empty()) cli::check_output("--md", md, {".md"}, inputs);
  s.budget = a.budget_mb > 0 ? static_cast<std::size_t>(a.budget_mb * 1e6) : available_memory_bytes();
  s.ec = load_edit_case(a.edit);
  if (a.scale != 1) s.scaled = scaled_for_prediction(s.ec, a.scale);
  s.predictor = s.scaled ? std::make_unique<RunPredictor>(s.scaled->mesh, s.scaled->edit)
                         : std::make_unique<RunPredictor>(s.ec.mesh, s.ec.edit);
  try {
    s.calibration = MachineCalibration::load(calibration_path());
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}; `deformbench advise --calibrate` measures it again", e.what()));
  }
  if (s.calibration.empty())
    fmt::print(stderr, "[advise] no calibration at {} (deformbench advise --calibrate): times are not predicted\n",
               calibration_path());
  s.scratch = std::make_unique<ScratchPrefix>("advise");
  std::vector<Row> rows = evaluate(s);
  s.scratch.reset();
  if (!a.predict_only) rank_rows(rows, a.frames);
  const std::string v = a.predict_only ? "" : verdict(rows, a.frames);
  fmt::print("{} ({} vertices), {} {} {}, {} frames, budget {} MB{}\n", s.ec.edit.name, s.ec.mesh.num_vertices(),
             to_string(s.given.options.method), to_string(s.given.options.constraints),
             to_string(s.given.options.build), a.frames, mb(static_cast<double>(s.budget)),
             s.scaled ? scale_note(*s.scaled, a.scale) : "");
  print_table(rows, a.predict_only);
  if (!v.empty()) fmt::print("{}\n{}\n", v, provenance_summary());
  StagedOutputs out;
  if (!a.csv.empty()) csv(s, rows).write(out.stage(a.csv));
  if (!md.empty())
    write_atomically(out.stage(md), [&](std::ostream& o) {
      o << "# deformbench advise " << s.ec.edit.name << "\n\n" << markdown(rows, a.predict_only) << "\n" << v
        << "\n\n" << provenance_summary() << "\n";
    });
  out.commit();
  return 0;
}

// --calibrate measures the machine: it takes --threads and --timeout-s, and would ignore an EDIT or any other
// option silently.
void check_calibrate(const CLI::App& app, const AdviseArgs& a) {
  if (!a.edit.empty()) throw UsageError(fmt::format("--calibrate measures this machine and takes no EDIT ({})", a.edit));
  for (const CLI::Option* o : app.get_options()) {
    const std::vector<std::string>& names = o->get_lnames();
    if (o->count() == 0 || names.empty()) continue;
    if (names[0] != "calibrate" && names[0] != "threads" && names[0] != "timeout-s")
      throw UsageError(fmt::format("--{} does not go with --calibrate (it takes --threads and --timeout-s only)",
                                   names[0]));
  }
}

}  // namespace

Command add_advise(CLI::App& tool) {
  auto a = std::make_shared<AdviseArgs>();
  CLI::App* app = tool.add_subcommand(
      "advise", "deform one edit with every applicable backend in fresh processes; rank them and give a verdict");
  app->add_option("edit", a->edit, "a Botsch-Sorkine stem or a .edit file (--calibrate: none)")->type_name("EDIT");
  add_deform_option_flags(*app, a->values, {}, {"memory_budget_mb", "factor_dir", "frame_mode"});
  app->add_option("--frames", a->frames, "frames of each run; the ranking is init + frames x frame")
      ->type_name("N")->check(cli::Integer(1, 100000))->capture_default_str();
  app->add_option("--threads", a->threads, "threads of every child (OpenMP, BLAS, assembly); default as now")
      ->type_name("T")->check(cli::Integer(1, 4096));
  app->add_option("--budget-mb", a->budget_mb, "memory budget of each run (default: the memory available now)")
      ->type_name("M")->check(cli::Real(1, 1e9));
  app->add_option("--timeout-s", a->timeout_s, "wall-clock limit of each child")
      ->type_name("S")->check(cli::Real(1, 1e6))->capture_default_str();
  app->add_option("--backends", a->backends, "only these backends (comma-separated)")->type_name("B,...");
  app->add_option("--csv", a->csv, "the ranked table as CSV (.csv), with provenance")->type_name("FILE");
  app->add_option("--md", a->md, "the ranked table as Markdown (.md; default: the --csv path with .md)")
      ->type_name("FILE");
  app->add_flag("--predict-only", a->predict_only, "print the predictions; run nothing");
  app->add_flag("--quick", a->quick, "no reference solution and no handle-frame runs (exp_predictions' cells)");
  app->add_option("--scale", a->scale, "predict for a mesh with K times the vertices (with --predict-only)")
      ->type_name("K")->check(cli::Real(1, 1e4));
  app->add_flag("--calibrate", a->calibrate, "measure this machine's rates for the predictions (a few minutes)");
  return {app, [app, a] {
            if (a->edit.empty() && !a->calibrate) throw UsageError("advise: an EDIT is required (or --calibrate)");
            if (a->calibrate) check_calibrate(*app, *a);
            if (a->scale != 1 && !a->predict_only) throw UsageError("--scale predicts only: add --predict-only");
            return run_advise(*app, *a);
          }};
}

}  // namespace db::commands
