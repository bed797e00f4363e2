// deformbench: command-line front end (`deformbench --help`; README "One deformation from the command line").
//   deformbench deform <edit> --out FILE [options]   one edit, its phase times and bytes
//   deformbench solvers                              the linear-solver backends, with what each accepts
//   deformbench provenance                           what result rows record about this machine and build
//   deformbench coat|transplant SOURCE TARGET --out FILE   the applications (apps/commands/)
//   mpirun -np N deformbench deform <edit> --solver mumps ...   one edit on N ranks (MUMPS distributed; rank 0
//                                                                prints and writes; the other subcommands refuse)
// Options are checked before any work: a value out of range, an option the chosen method or backend does not use,
// or an output that could not be written is a usage error (exit 1) before a mesh is read.
#include <algorithm>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "commands/commands.h"
#include "solvers/base/atomic_file.h"
#include "core/cli.h"
#include "core/csv.h"
#include "solvers/base/error.h"
#include "core/input_file.h"
#include "core/provenance.h"
#include "solvers/base/resources.h"
#include "edit/edit_io.h"
#include "edit/transform.h"
#include "harness/cell.h"
#include "harness/stats.h"
#include "mesh/mesh_io.h"
#include "methods/deformer.h"
#include "methods/drag.h"
#include "operators/frames.h"
#include "solvers/mumps_mpi.h"
#include "systems/min_quad_with_fixed.h"

namespace {

using namespace db;

const std::vector<std::string> kMeshExtensions = {".off", ".ply", ".obj"};  // what write_mesh writes
const std::vector<std::string> kMethods = {"lap", "tf", "lri"};
// Orderings the structured LAP / TF build applies to the vertex graph itself (systems/vertex_ordering.h).
const std::vector<std::string> kVertexOrderings = {"default", "natural", "amd", "metis", "nesdis"};

struct DeformArgs {
  std::string edit, out, csv, transform, factor_dir;
  std::string method = "lap", weights = "uniform", constraints = "hard", build = "structured", solver;
  std::string ordering = "default", lri_frames = "first", lri_orthonormalize = "gram_schmidt",
              lri_frame_control = "coordinated";
  std::string tf_scale = "free";
  std::string frame_mode = "full";
  std::string precision = "double";
  double soft_weight = 1.0, handle_limit = DeformOptions::kDefaultHandleLimit, refine_tolerance = 1e-10;
  long long refine_max_iterations = 1000;
  bool vs_double = false;
  unsigned lri_seed = 1;
  bool tf_no_translation = false, no_normalize = false;
  long long frames = 1, memory_budget_mb = 0;
};

bool contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

template <class E>
std::vector<std::string> names(std::initializer_list<E> values) {
  std::vector<std::string> out;
  for (E e : values) out.push_back(to_string(e));
  return out;
}

std::vector<std::string> all_orderings() {
  std::vector<std::string> out = kVertexOrderings;
  for (const std::string& s : solver_names())
    for (const std::string& o : solver_info(s).orderings)
      if (!contains(out, o)) out.push_back(o);
  return out;
}

std::vector<std::string> out_of_core_backends() {
  std::vector<std::string> out;
  for (const std::string& s : solver_names())
    if (solver_info(s).out_of_core) out.push_back(s);
  return out;
}

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
  d.add_option("--out", a.out, "the deformed mesh (.off, .ply or .obj); written only if the whole run succeeds")
      ->type_name("FILE")->required();
  d.add_option("--csv", a.csv, "also write one tidy CSV row (.csv) of the measurements, with --out, all or nothing")
      ->type_name("FILE");
  d.add_option("--frames", a.frames, "interpolate the handle transform over N frames; report the median frame (an edit's "
               "per-vertex targets: N of its frames, cycling; default all of them)")
      ->type_name("N")->transform(cli::Integer(1, kMaxFrames))->capture_default_str();
  d.add_option("--frame-mode", a.frame_mode,
               "full: each frame solves; handle: the responses to the handle's affine map are solved for once after "
               "the factorization and each frame streams them (lri: its frame system)")
      ->check(cli::OneOf(names({FrameMode::Full, FrameMode::Handle})))->capture_default_str();
  d.add_option("--handle-limit", a.handle_limit,
               "--frame-mode handle with per-vertex targets: keep full frames when the responses would exceed R "
               "times the factor's bytes (measured: results/handle_drags.md)")
      ->type_name("R")->check(cli::Real(1e-6, 1e6))->capture_default_str();
  d.add_option("--transform", a.transform,
               "replace the edit's handle transform: translate:x,y,z | rotate:DEG:ax,ay,az[:px,py,pz] | "
               "matrix:16 values | def:FILE")
      ->type_name("SPEC")->check(TransformSpec());
  const std::string m = "Method";
  d.add_option("--method", a.method, "the deformation method")->check(cli::OneOf(kMethods))->capture_default_str()
      ->group(m);
  d.add_option("--constraints", a.constraints, "eliminate the handle and fixed vertices, or keep them as weighted rows")
      ->check(cli::OneOf(names({ConstraintMode::Hard, ConstraintMode::Soft})))->capture_default_str()->group(m);
  d.add_option("--soft-weight", a.soft_weight, "weight w of the soft constraint rows w^2 |v - u|^2 (--constraints soft)")
      ->type_name("W")->check(cli::Real(1e-8, 1e8))->capture_default_str()->group(m);
  d.add_option("--weights", a.weights, "Laplacian weights (lap, tf)")
      ->check(cli::OneOf(names({Weights::Uniform, Weights::Cotan})))->capture_default_str()->group(m);
  d.add_flag("--tf-no-translation", a.tf_no_translation, "TF without the translation fit, thesis eq. 2-12 (tf)")
      ->group(m);
  d.add_option("--tf-scale", a.tf_scale,
               "free: TF's fitted similarities as they are; normalized: their rotations only, by a second LAP pass "
               "(tf)")
      ->check(cli::OneOf({"free", "normalized"}))->capture_default_str()->group(m);
  d.add_flag("--no-normalize", a.no_normalize, "build in raw coordinates (diagnosis only: TF may fail)")->group(m);
  const std::string l = "LRI (--method lri)";
  d.add_option("--lri-frames", a.lri_frames, "local frame strategy")
      ->check(cli::OneOf(names({FrameStrategy::First, FrameStrategy::Random, FrameStrategy::HeightAngle,
                                FrameStrategy::Curvature})))
      ->capture_default_str()->group(l);
  d.add_option("--lri-orthonormalize", a.lri_orthonormalize, "how solved frames are made rotations again")
      ->check(cli::OneOf(names({Orthonormalization::GramSchmidt, Orthonormalization::Polar})))
      ->capture_default_str()->group(l);
  d.add_option("--lri-frame-control", a.lri_frame_control,
               "coordinated: the handle's frames turn with its positions; uncoordinated: they stay at rest (thesis "
               "fig. 3-4)")
      ->check(cli::OneOf({"coordinated", "uncoordinated"}))->capture_default_str()->group(l);
  d.add_option("--lri-seed", a.lri_seed, "seed of --lri-frames random")
      ->type_name("N")->transform(cli::Integer(0, 4294967295LL))->capture_default_str()->group(l);
  const std::string s = "Linear system";
  d.add_option("--build", a.build, "how the normal matrix is formed (lri: structured or naive)")
      ->check(cli::OneOf(names({Build::Structured, Build::Naive, Build::Dense})))->capture_default_str()->group(s);
  d.add_option("--solver", a.solver,
               "linear-solver backend (default multifrontal, dense_llt for --build dense; `deformbench solvers`)")
      ->check(cli::OneOf(solver_names()))->group(s);
  d.add_option("--ordering", a.ordering,
               "fill-reducing ordering: of the vertex graph with the structured lap/tf build, else the backend's own "
               "(`deformbench solvers` lists what each accepts)")
      ->check(cli::OneOf(all_orderings()))->capture_default_str()->group(s);
  d.add_option("--factor-dir", a.factor_dir, fmt::format("out of core: the factor in scratch files in DIR ({})",
                                                      fmt::join(out_of_core_backends(), ", ")))
      ->type_name("DIR")->group(s);
  d.add_option("--memory-budget-mb", a.memory_budget_mb, "refuse builds predicted above MB megabytes (exit 4)")
      ->type_name("MB")->transform(cli::Integer(1, 1000000000))->group(s);
  const std::string p = "Precision";
  d.add_option("--precision", a.precision,
               "double, or mixed: the factor stored in single precision (multifrontal_mixed), each solve refined by "
               "CG in double")
      ->check(cli::OneOf({"double", "mixed"}))->capture_default_str()->group(p);
  d.add_option("--refine-tolerance", a.refine_tolerance,
               "mixed: refine each solve until a correction is below T of x (max-norms; not reached: exit 3)")
      ->type_name("T")->check(cli::Real(1e-16, 1e-2))->capture_default_str()->group(p);
  d.add_option("--refine-max-iterations", a.refine_max_iterations, "mixed: the refinement's iteration cap (exit 3)")
      ->type_name("N")->transform(cli::Integer(0, 100000))->capture_default_str()->group(p);
  d.add_flag("--vs-double", a.vs_double,
             "mixed: deform again with the double factor afterwards and report the largest difference")
      ->group(p);
}

//! The mixed-precision counterpart of the default sparse backend.
constexpr const char* kMixedBackend = "multifrontal_mixed";

// The backend this run uses: --solver, or the build's default.
std::string backend(const DeformArgs& a) {
  if (a.precision == "mixed") return kMixedBackend;
  return a.solver.empty() ? resolve_solver("", parse_build(a.build)) : a.solver;
}

// The backends whose solves are refined (--refine-*): the mixed-precision one and the double ones refined alike.
bool refines(const std::string& backend) {
  return backend == kMixedBackend || backend == "multifrontal_refined" || backend == "mumps_refined";
}
bool mixed(const DeformArgs& a) { return refines(backend(a)); }

// Options the chosen method, constraints or build do not use are refused, not ignored.
void refuse_unused(const CLI::App& d, const DeformArgs& a) {
  auto refuse = [&](const char* option, const std::string& why) {
    if (d.count(option) > 0) throw UsageError(fmt::format("{} {}", option, why));
  };
  const bool lri = a.method == "lri";
  if (lri) refuse("--weights", "is not used by --method lri (its systems have no Laplacian weights)");
  if (a.method != "tf")
    for (const char* o : {"--tf-no-translation", "--tf-scale"})
      refuse(o, fmt::format("is for --method tf only, not {}", a.method));
  if (!lri)
    for (const char* o : {"--lri-frames", "--lri-orthonormalize", "--lri-frame-control", "--lri-seed"})
      refuse(o, fmt::format("is for --method lri only, not {}", a.method));
  else if (a.lri_frames != "random")
    refuse("--lri-seed", fmt::format("is used by --lri-frames random only, not {}", a.lri_frames));
  if (a.constraints != "soft") refuse("--soft-weight", "weights soft constraints; it needs --constraints soft");
  if (a.frame_mode != "handle") refuse("--handle-limit", "bounds handle-mode responses; it needs --frame-mode handle");
  if (a.tf_scale == "normalized" && a.frame_mode == "handle")
    throw UsageError("--frame-mode handle with --tf-scale normalized: its second pass rotates by the fitted "
                     "rotations, so a frame is not affine in the handle map (use --frame-mode full)");
  if (a.precision == "mixed" && !a.solver.empty() && a.solver != "multifrontal" && a.solver != kMixedBackend)
    throw UsageError(fmt::format("--precision mixed is the multifrontal backend's ({}), not {}", kMixedBackend,
                                 a.solver));
  if (!mixed(a))
    for (const char* o : {"--refine-tolerance", "--refine-max-iterations", "--vs-double"})
      refuse(o, fmt::format("is for the refined backends only (--precision mixed, --solver {}, "
                            "multifrontal_refined or mumps_refined)",
                            kMixedBackend));
  if (a.build == "dense") {
    if (lri) throw UsageError("--build dense: lri offers the structured and naive builds only");
    refuse("--ordering", "does not apply to --build dense (the dense factorization orders nothing)");
  }
}

// The backend must take the build's matrix, the ordering and --factor-dir. The orderings mirror LaplacianDeformer:
// the structured LAP / TF build orders the vertex graph itself when the backend takes an ordered matrix as it is
// ("natural"); otherwise the backend orders, from its own list.
void check_backend(const CLI::App& d, const DeformArgs& a) {
  const SolverInfo info = solver_info(backend(a));
  if (a.build == "dense" && info.family != "dense")
    throw UsageError(fmt::format("--solver {} takes sparse input only; --build dense needs a dense backend ({})",
                                 info.name, info.family));
  if (!a.factor_dir.empty() && !info.out_of_core)
    throw UsageError(fmt::format("--factor-dir: {} cannot keep its factor out of core ({} can)", info.name,
                                 fmt::join(out_of_core_backends(), ", ")));
  if (d.count("--ordering") == 0) return;
  const bool vertex_graph = a.method != "lri" && a.build == "structured" && contains(info.orderings, "natural");
  const std::vector<std::string>& accepted = vertex_graph ? kVertexOrderings : info.orderings;
  if (!contains(accepted, a.ordering))
    throw UsageError(fmt::format("--ordering {} is not accepted by {} with --build {}{} (accepted: {})", a.ordering,
                                 info.name, a.build, a.method == "lri" ? " and --method lri" : "",
                                 fmt::join(accepted, ", ")));
}

DeformOptions deform_options(const DeformArgs& a) {
  DeformOptions o;
  o.method = a.method;
  o.weights = parse_weights(a.weights);
  o.constraints = parse_constraints(a.constraints);
  o.soft_weight = a.soft_weight;
  o.tf_translation = !a.tf_no_translation;
  o.tf_normalize_scale = a.tf_scale == "normalized";
  o.lri_frames = a.lri_frames;
  o.lri_orthonormalize = a.lri_orthonormalize;
  o.lri_seed = a.lri_seed;
  o.lri_uncoordinated = a.lri_frame_control == "uncoordinated";
  o.build = parse_build(a.build);
  o.solver = backend(a);
  o.solver_options.ordering = a.ordering;
  o.solver_options.factor_dir = a.factor_dir;
  if (mixed(a)) {
    o.solver_options.tolerance = a.refine_tolerance;
    o.solver_options.max_iterations = static_cast<int>(a.refine_max_iterations);
  }
  o.normalize = !a.no_normalize;
  o.memory_budget = static_cast<std::size_t>(a.memory_budget_mb) * 1000000;
  o.frame_mode = parse_frame_mode(a.frame_mode);
  o.handle_limit = a.handle_limit;
  return o;
}

// Every phase's median over the frames, with its spread (harness/stats.h).
struct FrameMedians {
  harness::Spread frame, rhs, solve, write, response, orthonormalize;
};

// What a run measured besides the deformer's report: every rank's peak RSS (one entry without a launcher; rank 0
// first), taken before any comparison run, and (--vs-double) the largest coordinate difference from the double
// solve over the bounding-box diagonal (negative: not measured).
struct RunExtras {
  std::vector<double> rss;
  std::vector<double> matrix;  //!< under a launcher: every rank's matrix bytes handed to the solvers (rank 0 first)
  double vs_double = -1;
};

// Runs `frames` frames, frame f (1-based) deformed by `frame`; the last frame's positions go to `result`.
FrameMedians run_frames(Deformer& deformer, long long frames, const std::function<Points(long long)>& frame,
                        Points& result) {
  std::vector<double> all, rhs, solve, write, response, ortho;
  for (long long f = 1; f <= frames; ++f) {
    result = frame(f);
    const PhaseTimes& t = deformer.times();
    all.push_back(t.frame());
    rhs.push_back(t.rhs);
    solve.push_back(t.solve);
    write.push_back(t.write);
    response.push_back(t.response);
    ortho.push_back(t.orthonormalize);
  }
  using harness::spread;
  return {spread(all), spread(rhs), spread(solve), spread(write), spread(response), spread(ortho)};
}

// The drag: the handle transform interpolated from the rest pose over the frames, or the edit's per-vertex targets
// frame by frame (cycling when --frames asks for more frames than the targets give).
FrameMedians drag(Deformer& deformer, const Edit& edit, long long frames, Points& result) {
  return run_frames(deformer, frames, [&](long long f) { return deform_frame(deformer, edit, f, frames); }, result);
}

// Every rank's peak RSS on rank 0 (one entry without a launcher); collective under one.
std::vector<double> rank_peak_rss(int ranks) {
  return ranks > 1 ? mpi::gather_to_root(double(peak_rss_bytes())) : std::vector<double>{double(peak_rss_bytes())};
}

std::string joined(const std::vector<double>& v, double unit, int digits = 0) {
  std::string s;
  for (double x : v) s += (s.empty() ? "" : " ") + fmt::format("{:.{}f}", x / unit, digits);
  return s;
}

void print_report(const EditCase& ec, const DeformOptions& o, const Deformer& deformer, long long frames,
                  const FrameMedians& m, const RunExtras& x) {
  const PhaseTimes& t = deformer.times();
  fmt::print("mesh {} ({} vertices, {} faces), edit {}: {} fixed, {} free, {} handle\n", ec.mesh.name,
             ec.mesh.num_vertices(), ec.mesh.num_faces(), ec.edit.name, ec.edit.count(Role::Fixed),
             ec.edit.count(Role::Free), ec.edit.count(Role::Handle));
  fmt::print("method {} | build {} | solver {} | constraints {}\n", o.method, to_string(o.build), o.solver,
             to_string(o.constraints));
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
  if (x.vs_double >= 0)
    fmt::print("  against the double solve ({}): largest coordinate difference {:.3g} of the bounding-box diagonal\n",
               o.solver == "mumps_refined" ? "mumps" : "multifrontal", x.vs_double);
  fmt::print("build {:.4f} s | analyze {:.4f} s | factorize {:.4f} s | init {:.4f} s\n", t.build, t.analyze,
             t.factorize, t.init());
  if (!deformer.frame_mode_note().empty()) fmt::print("note: {}\n", deformer.frame_mode_note());
  if (deformer.frame_mode() == FrameMode::Handle)
    fmt::print("precompute {:.4f} s (handle responses, {:.2f} MB streamed per frame) | init + precompute {:.4f} s\n",
               t.precompute, deformer.response_bytes() / 1e6, t.init() + t.precompute);
  fmt::print("per frame ({} mode, median of {}): {:.5f} s (medians: rhs {:.5f}, solve {:.5f}, write {:.5f}", to_string(
             deformer.frame_mode()), frames, m.frame.median, m.rhs.median, m.solve.median, m.write.median);
  if (deformer.frame_mode() == FrameMode::Handle) fmt::print(", responses {:.5f}", m.response.median);
  if (o.method == "lri") fmt::print(", of rhs orthonormalize {:.5f}", m.orthonormalize.median);
  const std::string flag = fmt::format(" (more than {:g}x apart: a thread waited on a descheduled worker or the "
                                       "machine was busy; the median may be unreliable)", harness::kSpreadFlagRatio);
  fmt::print(")\n{} ranged {:.5f} - {:.5f} s{}\n", m.frame.count < frames ? "frames after the first" : "frames",
             m.frame.min, m.frame.max, harness::spread_flagged(m.frame) ? flag : "");
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

CsvTable csv_table(const EditCase& ec, const DeformOptions& o, const Deformer& deformer, long long frames,
                   const FrameMedians& m, const RunExtras& x) {
  const PhaseTimes& t = deformer.times();
  const SystemReport& sys = deformer.systems().front();
  CsvTable csv;
  csv.add({{"mesh", ec.mesh.name},
           {"edit", ec.edit.name},
           {"vertices", std::to_string(ec.mesh.num_vertices())},
           {"faces", std::to_string(ec.mesh.num_faces())},
           {"handle", std::to_string(ec.edit.count(Role::Handle))},
           {"fixed", std::to_string(ec.edit.count(Role::Fixed))},
           {"method", o.method},
           {"weights", to_string(o.weights)},
           {"constraints", to_string(o.constraints)},
           {"build", to_string(o.build)},
           {"backend", o.solver},
           {"ordering", sys.factor.ordering_used},
           {"factor_storage", sys.factor.factor_on_disk ? "disk" : "memory"},
           {"n", std::to_string(sys.n)},
           {"nnz", std::to_string(sys.nnz)},
           {"nnz_factor", std::to_string(sys.factor.nnz_factor)},
           {"build_s", num(t.build)},
           {"analyze_s", num(t.analyze)},
           {"factorize_s", num(t.factorize)},
           {"init_s", num(t.init())},
           {"drag", ec.edit.targets.rows() > 0 ? "per_vertex" : "affine"},
           {"frame_mode", to_string(deformer.frame_mode())},
           {"precompute_s", num(t.precompute)},
           {"frames", std::to_string(frames)},
           {"frame_median_s", num(m.frame.median)},
           {harness::spread_name("frame_s", "min"), num(m.frame.min)},
           {harness::spread_name("frame_s", "max"), num(m.frame.max)},
           {harness::spread_name("frame_s", "reps"), std::to_string(m.frame.count)},
           {"response_median_s", num(m.response.median)},
           {harness::spread_name("response_s", "min"), num(m.response.min)},
           {harness::spread_name("response_s", "max"), num(m.response.max)},
           {harness::spread_name("response_s", "reps"), std::to_string(m.response.count)},
           {"response_bytes", std::to_string(deformer.response_bytes())},
           {"matrix_bytes", std::to_string(deformer.matrix_bytes())},
           {"factor_bytes", std::to_string(deformer.factor_bytes())},
           {"peak_rss_bytes", fmt::format("{:.0f}", x.rss.front())},
           {"ranks", std::to_string(x.rss.size())},
           {"peak_rss_rank_bytes", joined(x.rss, 1)},
           {"precision", sys.backend == kMixedBackend ? "mixed" : "double"},
           {"refine_iterations", refines(sys.backend) ? std::to_string(sys.factor.iterations) : ""},
           {"refine_residual", refines(sys.backend) ? num(sys.factor.achieved_tolerance) : ""},
           {"refine_correction", refines(sys.backend) ? num(sys.factor.last_correction) : ""},
           {"refine_tolerance", refines(sys.backend) ? num(o.solver_options.tolerance) : ""},
           {"mixed_vs_double", x.vs_double >= 0 ? num(x.vs_double) : ""}});
  return csv;
}

// Under a launcher with N > 1 ranks every rank runs the whole command (the same system on each); only the `mumps`
// backend then works with the others (solvers/mumps_ranks_solver.cpp). Returns N (1 without a launcher).
int check_ranks(const DeformArgs& a) {
  const int ranks = mpi::launched() ? mpi::size() : 1;
  if (ranks > 1 && backend(a) != "mumps" && backend(a) != "mumps_refined")
    throw UsageError(fmt::format("started on {} ranks: only --solver mumps or mumps_refined runs distributed under "
                                 "mpirun; --solver {} runs in one process (start it without mpirun)",
                                 ranks, backend(a)));
  return ranks;
}

// --vs-double: the last frame's positions again with the double factor, unrefined (the same options otherwise; mumps
// for mumps_refined, multifrontal else), their largest coordinate difference from `mixed` over the rest mesh's
// bounding-box diagonal.
double difference_from_double(const EditCase& ec, DeformOptions o, long long frames, const Points& mixed) {
  o.solver = o.solver == "mumps_refined" ? "mumps" : "multifrontal";  // mumps also on ranks
  const auto deformer = make_deformer(ec.mesh, ec.edit, o);
  const Points twin = deform_frame(*deformer, ec.edit, frames, frames);
  return (mixed - twin).cwiseAbs().maxCoeff() / bbox_diagonal(ec.mesh.V);
}

// The edit's files are read whole or held parsed: with --memory-budget-mb, files larger than the budget are
// refused before a byte of them is read.
void check_input_budget(const DeformArgs& a, const std::vector<std::string>& inputs) {
  const std::uint64_t bytes = input_bytes(inputs), budget = static_cast<std::uint64_t>(a.memory_budget_mb) * 1000000;
  if (budget > 0 && bytes > budget)
    throw BudgetError(fmt::format("the input files of edit {} hold {:.1f} MB, more than --memory-budget-mb {}", a.edit,
                                  bytes / 1e6, a.memory_budget_mb));
}

int cmd_deform(const CLI::App& d, const DeformArgs& a) {
  refuse_unused(d, a);
  check_backend(d, a);
  const int ranks = check_ranks(a);
  DeformOptions o = deform_options(a);
  if (ranks > 1) {  // lap and tf (structured build): each rank assembles its own share
    o.rank = mpi::rank();
    o.ranks = ranks;
  }
  // Outputs before any mesh is read: a run that could not write its results fails at once, not after the solve.
  const std::vector<std::string> inputs = edit_case_files(a.edit);
  cli::check_output("--out", a.out, kMeshExtensions, inputs);
  if (d.count("--csv") > 0) cli::check_output("--csv", a.csv, {".csv"}, inputs);
  if (d.count("--factor-dir") > 0) cli::check_directory("--factor-dir", a.factor_dir);
  check_input_budget(a, inputs);
  const Mat4 transform = a.transform.empty() ? Mat4::Identity() : parse_transform(a.transform);  // def:FILE: exit 2

  EditCase ec = load_edit_case(a.edit);
  if (ec.edit.targets.rows() == 0 && d.count("--handle-limit") > 0)
    throw UsageError(fmt::format("--handle-limit bounds the responses of per-vertex targets, but edit '{}' drags its "
                                 "handle by one affine transform (no 'targets' file), so it is not used",
                                 ec.edit.name));
  if (!a.transform.empty()) ec.edit.transform = transform;
  const long long frames = ec.edit.target_frames() > 0 && d.count("--frames") == 0 ? ec.edit.target_frames() : a.frames;
  if (ec.edit.targets.rows() > 0 && !a.transform.empty())
    throw UsageError(fmt::format("--transform replaces the handle transform, but edit '{}' drags per-vertex targets "
                                 "(its 'targets' file)", ec.edit.name));
  const auto deformer = make_deformer(ec.mesh, ec.edit, o);
  Points result;
  const FrameMedians m = drag(*deformer, ec.edit, frames, result);
  RunExtras extras;
  extras.rss = rank_peak_rss(ranks);
  if (ranks > 1) extras.matrix = mpi::gather_to_root(double(deformer->matrix_bytes()));
  // Every rank: on ranks the twin's solver (mumps) is collective too.
  if (a.vs_double) extras.vs_double = difference_from_double(ec, o, frames, result);
  if (ranks > 1 && mpi::rank() != 0) return 0;  // rank 0 prints and writes

  StagedOutputs outputs;  // the mesh and the CSV row land together or not at all
  Mesh deformed = ec.mesh;
  deformed.V = std::move(result);
  write_mesh(outputs.stage(a.out), deformed);
  print_report(ec, o, *deformer, frames, m, extras);
  if (!a.csv.empty()) csv_table(ec, o, *deformer, frames, m, extras).write(outputs.stage(a.csv));
  outputs.commit();
  fmt::print("wrote {}{}\n", a.out, a.csv.empty() ? "" : " and " + a.csv);
  return 0;
}

// One line a backend: its name first, then what the deform options may ask of it.
int cmd_solvers() {
  for (const std::string& s : solver_names()) {
    const SolverInfo info = solver_info(s);
    fmt::print("{:<24} {:<16} orderings {}{}\n", s, info.family, fmt::join(info.orderings, ","),
               info.out_of_core ? " | --factor-dir" : "");
  }
  return 0;
}

int cmd_provenance() {
  for (const auto& kv : provenance().columns()) std::cout << kv.first << ": " << kv.second << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("deformbench: linear mesh deformation (LAP, TF, LRI) with interchangeable linear solvers",
               "deformbench");
  app.require_subcommand(1);
  app.footer(fmt::format("Exit codes: 0 ok, 1 usage (an unknown option, a value out of range, options that do not go "
                         "together, an output that cannot be written), 2 bad input (a mesh, an edit, a selection), 3 "
                         "solver failure (singular, indefinite, non-finite), 4 over the memory budget.\n"
                         "--frames is capped at {}.",
                         kMaxFrames));
  DeformArgs a;
  CLI::App* deform = app.add_subcommand("deform", "deform one edit; print the phase times and bytes");
  add_deform_options(*deform, a);
  CLI::App* solvers = app.add_subcommand("solvers", "list the linear-solver backends and the orderings each accepts");
  CLI::App* prov = app.add_subcommand("provenance", "print what result rows record about this machine and build");
  const std::vector<commands::Command> apps = {commands::add_coat(app), commands::add_transplant(app)};
  const int code = cli::run(app, argc, argv, [&] {
    // Only deform runs on ranks; another subcommand would run once per rank, each writing the same output.
    if (!deform->parsed() && mpi::launched() && mpi::size() > 1)
      throw UsageError(fmt::format("started on {} ranks: only `deformbench deform --solver mumps` runs under mpirun; "
                                   "`{}` runs in one process (start it without mpirun)",
                                   mpi::size(), app.get_subcommands().front()->get_name()));
    for (const commands::Command& c : apps)
      if (c.app->parsed()) return c.run();
    if (deform->parsed()) return cmd_deform(*deform, a);
    if (solvers->parsed()) return cmd_solvers();
    if (prov->parsed()) return cmd_provenance();
    return 1;
  });
  // A failure on some ranks would leave the others waiting in a collective call: end them all with its code.
  if (code != 0 && mpi::launched() && mpi::size() > 1) mpi::abort_all(code);
  return code;
}
