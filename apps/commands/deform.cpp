// deformbench deform <edit> --out FILE [options]: one edit, its phase times and bytes. The deform options come
// from the one table (methods/deform_options.h): each row is an option here, set and checked (resolve_options)
// before a mesh is read; the CSV row is the deformation's record (methods/deform_record.h).
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "commands.h"
#include "solvers/base/atomic_file.h"
#include "core/cli.h"
#include "core/csv.h"
#include "solvers/base/error.h"
#include "core/input_file.h"
#include "core/progress.h"
#include "core/provenance.h"
#include "solvers/base/resources.h"
#include "core/spread.h"
#include "edit/edit_io.h"
#include "edit/transform.h"
#include "mesh/mesh_io.h"
#include "methods/deform_option_flags.h"
#include "methods/deform_options.h"
#include "methods/deform_record.h"
#include "methods/deformer.h"
#include "methods/drag.h"
#include "methods/run_prediction.h"
#include "solvers/linear_solver.h"
#include "solvers/mumps_mpi.h"

namespace db::commands {
namespace {

// What the command takes besides the deform options: the edit, its outputs and the drag.
struct DeformArgs {
  std::string edit, out, csv, transform;
  long long frames = 1;
  bool vs_double = false, progress = false;
  DeformOptionValues values;  // deform option key -> its text as given
};

// --transform is checked as text here (a usage error); a def:FILE is read with the edit (a bad file: exit 2).
CLI::Validator TransformSpec() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        if (s.rfind("def:", 0) == 0) return {};
        try {
          parse_transform(s);
        } catch (const InputError& e) {
          return e.what();
        }
        return {};
      },
      "");
}

void add_deform_options(CLI::App& d, DeformArgs& a) {
  d.add_option("edit", a.edit, "a Botsch-Sorkine stem (STEM.off|.ply|.obj + STEM.sel + STEM.def) or a .edit file")
      ->type_name("EDIT")->required();
  d.add_option("--out", a.out, "the deformed mesh (.off, .ply, .obj or .stl); written only if the whole run succeeds")
      ->type_name("FILE")->required();
  d.add_option("--csv", a.csv, "also write one tidy CSV row (.csv) of the measurements, with --out, all or nothing")
      ->type_name("FILE");
  d.add_option("--frames", a.frames, "interpolate the handle transform over N frames; report the median frame (an edit's "
               "per-vertex targets: N of its frames, cycling; default all of them)")
      ->type_name("N")->transform(cli::Integer(1, kMaxFrames))->capture_default_str();
  d.add_option("--transform", a.transform,
               "replace the edit's handle transform: translate:x,y,z | rotate:DEG:ax,ay,az[:px,py,pz] | "
               "matrix:16 values | def:FILE")
      ->type_name("SPEC")->check(TransformSpec());
  d.add_flag("--progress", a.progress,
             "frames done and time left on stderr while the drag runs (on by default when stderr is a terminal); "
             "at most one line per interval, none for a run shorter than it (docs/cli.md)");
  add_deform_option_flags(d, a.values);
  d.add_flag("--vs-double", a.vs_double,
             "with a refined backend (mixed precision or --solver ..._refined): deform again with the double factor, "
             "unrefined, afterwards and report the largest difference")
      ->group("Precision");
}

// The options as given, checked together, the solver resolved (resolve_options); --vs-double refused where the
// refinement options are.
DeformOptions options_of(const CLI::App& d, const DeformArgs& a) {
  const DeformOptions o = deform_options_given(d, a.values);
  if (a.vs_double)
    if (const std::string why = deform_option_def("refine_tolerance").unused(o); !why.empty())
      throw UsageError("--vs-double" + why);
  return o;
}

// What a run measured besides the deformation's record: every rank's peak RSS (one entry without a launcher; rank
// 0 first), taken before any comparison run, and (--vs-double) the largest coordinate difference from the double
// solve over the bounding-box diagonal (negative: not measured).
struct RunExtras {
  std::vector<double> rss;
  std::vector<double> matrix;  //!< under a launcher: every rank's matrix bytes handed to the solvers (rank 0 first)
  double vs_double = -1;
};

// Every rank's peak RSS on rank 0 (one entry without a launcher); collective under one.
std::vector<double> rank_peak_rss(int ranks) {
  return ranks > 1 ? mpi::gather_to_root(double(peak_rss_bytes())) : std::vector<double>{double(peak_rss_bytes())};
}

std::string joined(const std::vector<double>& v, double unit, int digits = 0) {
  std::string s;
  for (double x : v) s += (s.empty() ? "" : " ") + fmt::format("{:.{}f}", x / unit, digits);
  return s;
}

void print_systems(const DeformOptions& o, const Deformer& deformer) {
  for (const auto& s : deformer.systems())
    fmt::print("  system {}: n {} | nnz {} | ordering {} | matrix {:.2f} MB | factor {:.2f} MB{} (nnz(L) {}, {:.2f} GFlop) "
               "| min pivot/diagonal {:.3g}\n",
               s.name, s.n, s.nnz, s.factor.ordering_used, s.matrix_bytes / 1e6, s.factor.factor_bytes / 1e6,
               s.factor.factor_on_disk ? " on disk" : "", s.factor.nnz_factor, s.factor.flops / 1e9,
               s.factor.min_pivot_ratio);
  for (const auto& s : deformer.systems())
    if (s.factor.min_pivot_ratio > 0 && s.factor.min_pivot_ratio < singular_pivot_bound(s.n))
      fmt::print("  note: system {} is ill-conditioned: its smallest pivot is {:.2g} of its diagonal entry, under the "
                 "{:.2g} (10 n eps) a singular matrix's rounding noise reaches; the constraints pin its null space, so "
                 "it is solved, but expect fewer correct digits\n",
                 s.name, s.factor.min_pivot_ratio, singular_pivot_bound(s.n));
  for (const auto& s : deformer.systems())
    if (refines(s.backend))
      fmt::print("  refinement of system {} (last solve): {} CG iterations, last correction {:.3g} of x (tolerance "
                 "{:.3g}), relative residual {:.3g}\n",
                 s.name, s.factor.iterations, s.factor.last_correction, o.solver_options.tolerance,
                 s.factor.achieved_tolerance);
}

void print_frames(const DeformOptions& o, const Deformer& deformer, const Drag& g) {
  const PhaseTimes& t = deformer.times();
  if (!deformer.frame_mode_note().empty()) fmt::print("note: {}\n", deformer.frame_mode_note());
  if (deformer.frame_mode() == FrameMode::Handle)
    fmt::print("precompute {:.4f} s (handle responses, {:.2f} MB streamed per frame) | init + precompute {:.4f} s\n",
               t.precompute, deformer.response_bytes() / 1e6, t.init() + t.precompute);
  const Spread frame = spread(g.frame);
  const long long frames = static_cast<long long>(g.frame.size());
  fmt::print("per frame ({} mode, median of {}): {:.5f} s (medians: rhs {:.5f}, solve {:.5f}, write {:.5f}",
             to_string(deformer.frame_mode()), frames, frame.median, median(g.rhs), median(g.solve), median(g.write));
  if (deformer.frame_mode() == FrameMode::Handle) fmt::print(", responses {:.5f}", median(g.response));
  if (o.method == Method::Lri) fmt::print(", of rhs orthonormalize {:.5f}", median(g.orthonormalize));
  const std::string flag = fmt::format(" (more than {:g}x apart: a thread waited on a descheduled worker or the "
                                       "machine was busy; the median may be unreliable)", kSpreadFlagRatio);
  fmt::print(")\n{} ranged {:.5f} - {:.5f} s{}\n", frame.count < frames ? "frames after the first" : "frames",
             frame.min, frame.max, spread_flagged(frame) ? flag : "");
}

void print_report(const EditCase& ec, const DeformOptions& o, const Deformer& deformer, const Drag& g,
                  const RunExtras& x) {
  const PhaseTimes& t = deformer.times();
  fmt::print("mesh {} ({} vertices, {} faces), edit {}: {} fixed, {} free, {} handle\n", ec.mesh.name,
             ec.mesh.num_vertices(), ec.mesh.num_faces(), ec.edit.name, ec.edit.count(Role::Fixed),
             ec.edit.count(Role::Free), ec.edit.count(Role::Handle));
  fmt::print("method {} | build {} | solver {} | constraints {}\n", to_string(o.method), to_string(o.build), o.solver,
             to_string(o.constraints));
  print_systems(o, deformer);
  if (x.vs_double >= 0)
    fmt::print("  against the double solve ({}): largest coordinate difference {:.3g} of the bounding-box diagonal\n",
               o.solver == "mumps_refined" ? "mumps" : "multifrontal", x.vs_double);
  fmt::print("build {:.4f} s | analyze {:.4f} s | factorize {:.4f} s | init {:.4f} s\n", t.build, t.analyze,
             t.factorize, t.init());
  print_frames(o, deformer, g);
  double flops = 0;
  for (const auto& s : deformer.systems()) flops += s.factor.flops;
  fmt::print("matrix {:.2f} MB | factor {:.2f} MB ({:.1f} GFlop/s in factorize) | peak RSS {:.1f} MB\n",
             deformer.matrix_bytes() / 1e6, deformer.factor_bytes() / 1e6,
             t.factorize > 0 ? flops / 1e9 / t.factorize : 0.0, x.rss.front() / 1e6);
  if (x.rss.size() > 1)
    fmt::print("{} ranks (MUMPS distributed; times are rank 0's) | peak RSS per rank MB: {} | max {:.1f} MB | "
               "matrix per rank MB: {}\n",
               x.rss.size(), joined(x.rss, 1e6), *std::max_element(x.rss.begin(), x.rss.end()) / 1e6,
               joined(x.matrix, 1e6, 2));
  fmt::print("{}\n", provenance_summary());
}

// The CSV row: the deformation's record, then what only the command line sees. Not measured (NaN): empty.
CsvTable csv_table(DeformRecord record, const RunExtras& x) {
  add_number(record, "peak_rss_bytes", x.rss.front(), "bytes");
  add_number(record, "ranks", static_cast<double>(x.rss.size()), "count");
  add_text(record, "peak_rss_rank_bytes", joined(x.rss, 1));
  add_number(record, "mixed_vs_double", x.vs_double >= 0 ? x.vs_double : std::nan(""), "bbox_diagonal");
  CsvTable::Row row;
  for (const RecordField& f : record)
    row.emplace_back(f.name, f.is_text() ? f.text : std::isnan(f.value) ? "" : num(f.value));
  CsvTable csv;
  csv.add(std::move(row));
  return csv;
}

// Under a launcher with N > 1 ranks every rank runs the whole command (the same system on each); only the `mumps`
// backend then works with the others (solvers/mumps_ranks_solver.cpp). Returns N (1 without a launcher).
int check_ranks(const DeformOptions& o) {
  const int ranks = mpi::launched() ? mpi::size() : 1;
  if (ranks > 1 && o.solver != "mumps" && o.solver != "mumps_refined")
    throw UsageError(fmt::format("started on {} ranks: only --solver mumps or mumps_refined runs distributed under "
                                 "mpirun; --solver {} runs in one process (start it without mpirun)",
                                 ranks, o.solver));
  return ranks;
}

// --vs-double: the last frame's positions again with the double factor, unrefined (the same options otherwise; mumps
// for mumps_refined, multifrontal else), their largest coordinate difference from `mixed` over the rest mesh's
// bounding-box diagonal.
double difference_from_double(const EditCase& ec, DeformOptions o, long long frames, const Points& mixed) {
  o.solver = o.solver == "mumps_refined" ? "mumps" : "multifrontal";  // mumps also on ranks
  o.precision = Precision::Double;
  const auto deformer = make_deformer(ec.mesh, ec.edit, o);
  const Points twin = deform_frame(*deformer, ec.edit, frames, frames);
  return (mixed - twin).cwiseAbs().maxCoeff() / bbox_diagonal(ec.mesh.V);
}

// The edit's files are read whole or held parsed: with --memory-budget-mb, files larger than the budget are
// refused before a byte of them is read.
void check_input_budget(const DeformArgs& a, const DeformOptions& o, const std::vector<std::string>& inputs) {
  const std::uint64_t bytes = input_bytes(inputs), budget = o.memory_budget;
  if (budget > 0 && bytes > budget)
    throw BudgetError(fmt::format("the input files of edit {} hold {:.1f} MB, more than --memory-budget-mb {}", a.edit,
                                  bytes / 1e6, budget / 1000000));
}

// The run's predicted peak memory (methods/run_prediction.h; the vertex graph ordered by AMD, cheaper than the
// run's METIS but serial) against the budget, before anything is built (guard_memory says for which backends).
void check_predicted_memory(const CLI::App& d, const EditCase& ec, const DeformOptions& o) {
  MachineCalibration calibration;
  try {  // a stale or damaged calibration costs the check its measured ratios, not the run
    calibration = MachineCalibration::load(calibration_path());
  } catch (const InputError& e) {
    fmt::print(stderr, "deform: calibration ignored ({}); `deformbench advise --calibrate` measures it again\n",
               e.what());
  }
  const RunPrediction p = predict_run(ec.mesh, ec.edit, o, calibration, 1, false);
  if (p.peak_bytes <= static_cast<double>(o.memory_budget)) return;
  throw BudgetError(fmt::format(
      "{} {} with {} is predicted to peak at {:.1f} MB (system {:.1f} MB, factor {:.1f} MB), over {}; not started",
      to_string(o.method), to_string(o.build), resolve_options(o).solver, p.peak_bytes / 1e6, p.build_bytes / 1e6,
      (p.factor_bytes + p.workspace_bytes) / 1e6,
      d.count("--memory-budget-mb") > 0
          ? fmt::format("--memory-budget-mb {}", o.memory_budget / 1000000)
          : fmt::format("the memory available ({:.1f} MB, the default budget; --memory-budget-mb overrides it)",
                        o.memory_budget / 1e6)));
}

// The memory budget (--memory-budget-mb, else the memory available when the run starts) for the factorization's
// peak. A backend that knows its factor's exact size after its analysis (SolverInfo::checks_memory: the default
// one) checks it there, before allocating the factor: the prediction would order the vertex graph once more
// (AMD, on one core), which on many cores costs a large part of the init itself
// (results/records/2026-11-27-init-floor). For the others the peak is predicted before anything is built. Out of
// core (--factor-dir) the factor is not resident: neither check, which would refuse the very runs the option is
// for (the build's own budget check still applies).
void guard_memory(const CLI::App& d, const EditCase& ec, DeformOptions& o) {
  if (o.memory_budget == 0 || !o.solver_options.factor_dir.empty()) return;
  if (solver_info(resolve_options(o).solver).checks_memory)
    o.solver_options.memory_budget = o.memory_budget;
  else
    check_predicted_memory(d, ec, o);
}

// Runs f. The build's and the backend's own budget checks (guard_memory) name the budget but not its source:
// without --memory-budget-mb it is the memory available when the run started.
template <class F>
auto naming_budget_source(const CLI::App& d, F&& f) {
  try {
    return f();
  } catch (const BudgetError& e) {
    if (d.count("--memory-budget-mb") > 0) throw;
    throw BudgetError(fmt::format("{} (the budget: the memory available when the run started; --memory-budget-mb "
                                  "overrides it)", e.what()));
  }
}

// The edit with --transform applied; --handle-limit and --transform refused where the edit leaves them unused.
EditCase load_edit(const CLI::App& d, const DeformArgs& a, const Mat4& transform) {
  EditCase ec = load_edit_case(a.edit);
  if (ec.edit.targets.rows() == 0 && d.count("--handle-limit") > 0)
    throw UsageError(fmt::format("--handle-limit bounds the responses of per-vertex targets, but edit '{}' drags its "
                                 "handle by one affine transform (no 'targets' file), so it is not used",
                                 ec.edit.name));
  if (ec.edit.targets.rows() > 0 && !a.transform.empty())
    throw UsageError(fmt::format("--transform replaces the handle transform, but edit '{}' drags per-vertex targets "
                                 "(its 'targets' file)", ec.edit.name));
  if (!a.transform.empty()) ec.edit.transform = transform;
  return ec;
}

int run_deform(const CLI::App& d, const DeformArgs& a) {
  DeformOptions o = options_of(d, a);
  if (d.count("--memory-budget-mb") == 0) o.memory_budget = available_memory_bytes();  // 0: unknown, unlimited
  const int ranks = check_ranks(o);
  if (ranks > 1) {  // lap and tf (structured build): each rank assembles its own share
    o.rank = mpi::rank();
    o.ranks = ranks;
  }
  // Outputs before any mesh is read: a run that could not write its results fails at once, not after the solve.
  const std::vector<std::string> inputs = edit_case_files(a.edit);
  cli::check_output("--out", a.out, mesh_extensions(), inputs);
  if (d.count("--csv") > 0) cli::check_output("--csv", a.csv, {".csv"}, inputs);
  if (d.count("--factor-dir") > 0) cli::check_directory("--factor-dir", o.solver_options.factor_dir);
  check_input_budget(a, o, inputs);
  const Mat4 transform = a.transform.empty() ? Mat4::Identity() : parse_transform(a.transform);  // def:FILE: exit 2

  const EditCase ec = load_edit(d, a, transform);
  if (ranks == 1) guard_memory(d, ec, o);
  const long long frames = ec.edit.target_frames() > 0 && d.count("--frames") == 0 ? ec.edit.target_frames() : a.frames;
  const auto deformer = naming_budget_source(d, [&] { return make_deformer(ec.mesh, ec.edit, o); });
  Progress progress("deform: frame", frames, (a.progress || stderr_is_terminal()) && (ranks <= 1 || mpi::rank() == 0));
  const Drag g = drag(*deformer, ec.edit, frames, [&progress](long long f) { progress(f); });
  RunExtras extras;
  extras.rss = rank_peak_rss(ranks);
  if (ranks > 1) extras.matrix = mpi::gather_to_root(double(deformer->matrix_bytes()));
  // Every rank: on ranks the twin's solver (mumps) is collective too.
  if (a.vs_double)
    extras.vs_double = naming_budget_source(d, [&] { return difference_from_double(ec, o, frames, g.V); });
  if (ranks > 1 && mpi::rank() != 0) return 0;  // rank 0 prints and writes

  StagedOutputs outputs;  // the mesh and the CSV row land together or not at all
  Mesh deformed = ec.mesh;
  deformed.V = g.V;
  write_mesh(outputs.stage(a.out), deformed);
  print_report(ec, o, *deformer, g, extras);
  if (!a.csv.empty())
    csv_table(deform_record(ec.mesh, ec.edit, o, *deformer, g), extras).write(outputs.stage(a.csv));
  outputs.commit();
  fmt::print("wrote {}{}\n", a.out, a.csv.empty() ? "" : " and " + a.csv);
  return 0;
}

}  // namespace

Command add_deform(CLI::App& tool) {
  auto a = std::make_shared<DeformArgs>();
  CLI::App* app = tool.add_subcommand("deform", "deform one edit; print the phase times and bytes");
  add_deform_options(*app, *a);
  return {app, [app, a] { return run_deform(*app, *a); }};
}

Command add_deform_options_listing(CLI::App& tool) {
  CLI::App* app = tool.add_subcommand("deform-options", "print the deform options as a Markdown list (docs/cli.md)");
  return {app, [] {
            fmt::print("{}", deform_options_markdown());
            return 0;
          }};
}

}  // namespace db::commands
