#include "methods/deform_options.h"

#include <algorithm>
#include <sstream>

#include <fmt/format.h>

#include "core/cli.h"
#include "core/csv.h"
#include "solvers/base/error.h"
#include "systems/min_quad_with_fixed.h"

namespace db {

const EnumText<Method>& enum_text(Method) {
  static const EnumText<Method> t{"method", {{Method::Lap, "lap"}, {Method::Tf, "tf"}, {Method::Lri, "lri"}}};
  return t;
}
const EnumText<ConstraintMode>& enum_text(ConstraintMode) {
  static const EnumText<ConstraintMode> t{"constraint mode",
                                          {{ConstraintMode::Hard, "hard"}, {ConstraintMode::Soft, "soft"}}};
  return t;
}
const EnumText<FrameMode>& enum_text(FrameMode) {
  static const EnumText<FrameMode> t{"frame mode", {{FrameMode::Full, "full"}, {FrameMode::Handle, "handle"}}};
  return t;
}
const EnumText<TfScale>& enum_text(TfScale) {
  static const EnumText<TfScale> t{"TF scale", {{TfScale::Free, "free"}, {TfScale::Normalized, "normalized"}}};
  return t;
}
const EnumText<FrameControl>& enum_text(FrameControl) {
  static const EnumText<FrameControl> t{
      "LRI frame control", {{FrameControl::Coordinated, "coordinated"}, {FrameControl::Uncoordinated, "uncoordinated"}}};
  return t;
}
const EnumText<Precision>& enum_text(Precision) {
  static const EnumText<Precision> t{"precision", {{Precision::Double, "double"}, {Precision::Mixed, "mixed"}}};
  return t;
}

bool refines(const std::string& backend) {
  return backend == kMixedBackend || backend == "multifrontal_refined" || backend == "mumps_refined";
}

namespace {

bool contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

// Orderings the structured LAP / TF build applies to the vertex graph itself (systems/vertex_ordering.h).
const std::vector<std::string> kVertexOrderings = {"default", "natural", "amd", "metis", "nesdis", "ringnd"};

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

using Unused = std::function<std::string(const DeformOptions&)>;
const Unused kAlwaysUsed = [](const DeformOptions&) { return std::string(); };

std::string flag_of(const std::string& key) {
  std::string f = "--" + key;
  std::replace(f.begin(), f.end(), '_', '-');
  return f;
}

DeformOptionDef row(const std::string& key, const std::string& group, const std::string& help) {
  DeformOptionDef d;
  d.key = key;
  d.flag = flag_of(key);
  d.group = group;
  d.help = help;
  d.unused = kAlwaysUsed;
  return d;
}

// A value from a list of names.
DeformOptionDef choice_row(const std::string& key, const std::string& group, const std::string& help,
                           std::vector<std::string> choices, std::function<void(DeformOptions&, const std::string&)> set,
                           std::function<std::string(const DeformOptions&)> get) {
  DeformOptionDef d = row(key, group, help);
  d.choices = std::move(choices);
  d.check = cli::OneOf(d.choices);
  d.set = std::move(set);
  d.get = std::move(get);
  return d;
}

// An enum field: its names from its one text table.
template <class E>
DeformOptionDef enum_row(const std::string& key, const std::string& group, const std::string& help,
                         E DeformOptions::*field) {
  return choice_row(
      key, group, help, enum_names<E>(), [field](DeformOptions& o, const std::string& s) { o.*field = parse_enum<E>(s); },
      [field](const DeformOptions& o) { return to_string(o.*field); });
}

// The field a row sets: one of DeformOptions, or one of its SolverOptions.
template <class T>
T& field_of(DeformOptions& o, T DeformOptions::*field) {
  return o.*field;
}
template <class T>
T& field_of(DeformOptions& o, T SolverOptions::*field) {
  return o.solver_options.*field;
}
template <class T, class S>
const T& field_of(const DeformOptions& o, T S::*field) {
  return field_of(const_cast<DeformOptions&>(o), field);
}

// A number field: checked as the command line checks numbers (core/cli.h), in [min, max].
template <class T, class S>
DeformOptionDef number_row(const std::string& key, const std::string& group, const std::string& value_name,
                           const std::string& help, T S::*field, double min, double max) {
  DeformOptionDef d = row(key, group, help);
  d.value_name = value_name;
  d.range = fmt::format("[{:.10g}, {:.10g}]", min, max);
  if constexpr (std::is_integral_v<T>)
    d.check = cli::Integer(static_cast<long long>(min), static_cast<long long>(max));
  else
    d.check = cli::Real(min, max);
  d.set = [field](DeformOptions& o, const std::string& s) { field_of(o, field) = static_cast<T>(std::stod(s)); };
  d.get = [field](const DeformOptions& o) {
    if constexpr (std::is_integral_v<T>)
      return std::to_string(field_of(o, field));
    else
      return num(field_of(o, field));
  };
  return d;
}

// A switch: given, it sets the field to `on` (key=value: 1 sets it, 0 leaves the default).
DeformOptionDef switch_row(const std::string& key, const std::string& group, const std::string& help,
                           bool DeformOptions::*field, bool on) {
  DeformOptionDef d = row(key, group, help);
  d.is_switch = true;
  d.check = cli::Integer(0, 1);
  d.set = [field, on](DeformOptions& o, const std::string& s) { o.*field = s == "1" ? on : !on; };
  d.get = [field, on](const DeformOptions& o) { return o.*field == on ? std::string("1") : std::string("0"); };
  return d;
}

std::string only_for(Method m, const DeformOptions& o) {
  return o.method == m ? "" : fmt::format(" is for --method {} only, not {}", to_string(m), to_string(o.method));
}

const std::string kGeneral = "", kMethod = "Method", kLri = "LRI (--method lri)", kSystem = "Linear system",
                  kPrecision = "Precision";

std::vector<DeformOptionDef> make_defs() {
  std::vector<DeformOptionDef> t;
  t.push_back(enum_row("frame_mode", kGeneral,
                       "full: each frame solves; handle: the responses to the handle's affine map are solved for once "
                       "after the factorization and each frame streams them (lri: its frame system)",
                       &DeformOptions::frame_mode));
  t.push_back(number_row("handle_limit", kGeneral, "R",
                         "--frame-mode handle with per-vertex targets: keep full frames when the responses would "
                         "exceed R times the factor's bytes (measured: results/records/2026-11-24-handle-frames/)",
                         &DeformOptions::handle_limit, 1e-6, 1e6));
  t.back().unused = [](const DeformOptions& o) {
    return o.frame_mode == FrameMode::Handle ? "" : " bounds handle-mode responses; it needs --frame-mode handle";
  };
  t.push_back(enum_row("method", kMethod, "the deformation method", &DeformOptions::method));
  t.push_back(enum_row("constraints", kMethod, "eliminate the handle and fixed vertices, or keep them as weighted rows",
                       &DeformOptions::constraints));
  t.push_back(number_row("soft_weight", kMethod, "W",
                         "weight w of the soft constraint rows w^2 |v - u|^2 (--constraints soft)",
                         &DeformOptions::soft_weight, 1e-8, 1e8));
  t.back().unused = [](const DeformOptions& o) {
    return o.constraints == ConstraintMode::Soft ? "" : " weights soft constraints; it needs --constraints soft";
  };
  t.push_back(enum_row("weights", kMethod, "Laplacian weights (lap, tf)", &DeformOptions::weights));
  t.back().unused = [](const DeformOptions& o) {
    return o.method == Method::Lri ? " is not used by --method lri (its systems have no Laplacian weights)" : "";
  };
  t.push_back(switch_row("tf_no_translation", kMethod, "TF without the translation fit, thesis eq. 2-12 (tf)",
                         &DeformOptions::tf_translation, false));
  t.back().unused = [](const DeformOptions& o) { return only_for(Method::Tf, o); };
  t.push_back(enum_row("tf_scale", kMethod,
                       "free: TF's fitted similarities as they are; normalized: their rotations only, by a second LAP "
                       "pass (tf)",
                       &DeformOptions::tf_scale));
  t.back().unused = [](const DeformOptions& o) { return only_for(Method::Tf, o); };
  t.push_back(switch_row("no_normalize", kMethod, "build in raw coordinates (diagnosis only: TF may fail)",
                         &DeformOptions::normalize, false));
  t.push_back(enum_row("lri_frames", kLri, "local frame strategy", &DeformOptions::lri_frames));
  t.push_back(enum_row("lri_orthonormalize", kLri, "how solved frames are made rotations again",
                       &DeformOptions::lri_orthonormalize));
  t.push_back(enum_row("lri_frame_control", kLri,
                       "coordinated: the handle's frames turn with its positions; uncoordinated: they stay at rest "
                       "(thesis fig. 3-4)",
                       &DeformOptions::lri_frame_control));
  t.push_back(number_row("lri_seed", kLri, "N", "seed of --lri-frames random", &DeformOptions::lri_seed, 0,
                         4294967295.0));
  for (auto it = t.end() - 4; it != t.end(); ++it) it->unused = [](const DeformOptions& o) { return only_for(Method::Lri, o); };
  t.back().unused = [](const DeformOptions& o) {
    if (o.method != Method::Lri) return only_for(Method::Lri, o);
    return o.lri_frames == FrameStrategy::Random
               ? std::string()
               : fmt::format(" is used by --lri-frames random only, not {}", to_string(o.lri_frames));
  };
  t.push_back(enum_row("build", kSystem, "how the normal matrix is formed (lri: structured or naive)",
                       &DeformOptions::build));
  t.push_back(choice_row(
      "backend", kSystem,
      "linear-solver backend (default multifrontal, dense_llt for --build dense; `deformbench solvers`)",
      solver_names(), [](DeformOptions& o, const std::string& s) { o.solver = s; },
      [](const DeformOptions& o) { return o.solver; }));
  t.back().flag = "--solver";
  t.push_back(choice_row(
      "ordering", kSystem,
      "fill-reducing ordering: of the vertex graph with the structured lap/tf build, else the backend's own "
      "(`deformbench solvers` lists what each accepts)",
      all_orderings(), [](DeformOptions& o, const std::string& s) { o.solver_options.ordering = s; },
      [](const DeformOptions& o) { return o.solver_options.ordering; }));
  t.back().unused = [](const DeformOptions& o) {
    return o.build == Build::Dense ? " does not apply to --build dense (the dense factorization orders nothing)" : "";
  };
  DeformOptionDef dir = row("factor_dir", kSystem,
                            fmt::format("out of core: the factor in scratch files in DIR ({})",
                                        fmt::join(out_of_core_backends(), ", ")));
  dir.value_name = "DIR";
  dir.check = [](std::string&) { return std::string(); };
  dir.set = [](DeformOptions& o, const std::string& s) { o.solver_options.factor_dir = s; };
  dir.get = [](const DeformOptions& o) { return o.solver_options.factor_dir; };
  dir.unused = [](const DeformOptions& o) {
    return o.solver.empty() || solver_info(o.solver).out_of_core
               ? std::string()
               : fmt::format(": {} cannot keep its factor out of core ({} can)", o.solver,
                             fmt::join(out_of_core_backends(), ", "));
  };
  t.push_back(dir);
  t.push_back(number_row("cg_tolerance", kSystem, "T",
                         "iterative backends: solve until the relative residual is below T", &DeformOptions::cg_tolerance,
                         1e-16, 1e-2));
  t.back().unused = [](const DeformOptions& o) {
    return !o.solver.empty() && solver_info(o.solver).family == "iterative"
               ? std::string()
               : std::string(" is for the iterative backends only (cg_jacobi, cg_ichol)");
  };
  DeformOptionDef budget = row("memory_budget_mb", kSystem,
                               "refuse runs whose peak memory would pass MB megabytes (exit 4): the multifrontal "
                               "backends check their factor's exact size before factoring, the others a "
                               "prediction before the build; default: the memory available when the run starts "
                               "(MemAvailable)");
  budget.value_name = "MB";
  budget.range = "[1, 1000000000]";
  budget.check = cli::Integer(1, 1000000000);
  budget.set = [](DeformOptions& o, const std::string& s) { o.memory_budget = std::stoull(s) * 1000000; };
  budget.get = [](const DeformOptions& o) {
    // A budget set in code that is not a whole number of MB has no text here (a cell keeps its bytes itself).
    return o.memory_budget == 0 || o.memory_budget % 1000000 != 0 ? std::string()
                                                                  : std::to_string(o.memory_budget / 1000000);
  };
  t.push_back(budget);
  t.push_back(enum_row("precision", kPrecision,
                       "double, or mixed: the factor stored in single precision (multifrontal_mixed), each solve "
                       "refined by CG in double",
                       &DeformOptions::precision));
  t.push_back(number_row("refine_tolerance", kPrecision, "T",
                         "mixed: refine each solve until a correction is below T of x (max-norms; not reached: exit 3)",
                         &SolverOptions::tolerance, 1e-16, 1e-2));
  t.push_back(number_row("refine_max_iterations", kPrecision, "N", "mixed: the refinement's iteration cap (exit 3)",
                         &SolverOptions::max_iterations, 0, 100000));
  for (auto it = t.end() - 2; it != t.end(); ++it)
    it->unused = [](const DeformOptions& o) {
      return refines(o.solver) ? std::string()
                               : fmt::format(" is for the refined backends only (--precision mixed, --solver {}, "
                                             "multifrontal_refined or mumps_refined)",
                                             kMixedBackend);
    };
  return t;
}

// A backend that cannot take the precision or the build: before the solver is resolved.
void check_backend(const DeformOptions& o) {
  if (o.precision == Precision::Mixed && !o.solver.empty() && o.solver != "multifrontal" && o.solver != kMixedBackend)
    throw UsageError(fmt::format("--precision mixed is the multifrontal backend's ({}), not {}", kMixedBackend,
                                 o.solver));
  if (o.build == Build::Dense && o.method == Method::Lri)
    throw UsageError("--build dense: lri offers the structured and naive builds only");
  if (o.build == Build::Dense && !o.solver.empty() && solver_info(o.solver).family != "dense")
    throw UsageError(fmt::format("--solver {} takes sparse input only; --build dense needs a dense backend ({})",
                                 o.solver, solver_info(o.solver).family));
}

// Options that do not go together, whether given or set in code.
void check_combinations(const DeformOptions& o) {
  if (o.tf_scale == TfScale::Normalized && o.method != Method::Tf)
    throw UsageError(fmt::format("--tf-scale normalized is for --method tf only, not {}", to_string(o.method)));
  if (o.tf_scale == TfScale::Normalized && o.frame_mode == FrameMode::Handle)
    throw UsageError("--frame-mode handle with --tf-scale normalized: its second pass rotates by the fitted "
                     "rotations, so a frame is not affine in the handle map (use --frame-mode full)");
}

// The orderings mirror LaplacianDeformer: the structured LAP / TF build orders the vertex graph itself when the
// backend takes an ordered matrix as it is ("natural"); otherwise the backend orders, from its own list.
void check_ordering(const DeformOptions& o) {
  const SolverInfo info = solver_info(o.solver);
  const bool vertex_graph = o.method != Method::Lri && o.build == Build::Structured && contains(info.orderings, "natural");
  const std::vector<std::string>& accepted = vertex_graph ? kVertexOrderings : info.orderings;
  if (!contains(accepted, o.solver_options.ordering))
    throw UsageError(fmt::format("--ordering {} is not accepted by {} with --build {}{} (accepted: {})",
                                 o.solver_options.ordering, info.name, to_string(o.build),
                                 o.method == Method::Lri ? " and --method lri" : "", fmt::join(accepted, ", ")));
}

}  // namespace

const std::vector<DeformOptionDef>& deform_option_defs() {
  static const std::vector<DeformOptionDef> defs = make_defs();
  return defs;
}

const DeformOptionDef& deform_option_def(const std::string& key) {
  for (const DeformOptionDef& d : deform_option_defs())
    if (d.key == key) return d;
  throw UsageError(fmt::format("unknown deform option '{}'", key));
}

void set_deform_option(DeformOptions& o, const std::string& key, const std::string& text) {
  const DeformOptionDef& d = deform_option_def(key);
  std::string value = text;
  if (const std::string why = d.check(value); !why.empty()) throw UsageError(fmt::format("{}: {}", d.flag, why));
  d.set(o, value);
}

std::vector<std::pair<std::string, std::string>> deform_option_items(const DeformOptions& o, const DeformOptions& base) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const DeformOptionDef& d : deform_option_defs())
    if (d.get(o) != d.get(base)) out.emplace_back(d.key, d.get(o));
  return out;
}

DeformOptions resolve_options(DeformOptions o, const std::vector<std::string>& given) {
  for (const DeformOptionDef& d : deform_option_defs()) {  // values set in code are checked as text would be
    std::string value = d.get(o);
    if (value.empty() || d.is_switch) continue;
    if (const std::string why = d.check(value); !why.empty()) throw UsageError(fmt::format("{}: {}", d.flag, why));
  }
  check_backend(o);
  if (o.precision == Precision::Mixed) o.solver = kMixedBackend;
  o.solver = resolve_solver(o.solver, o.build);
  for (const std::string& key : given)
    if (const std::string why = deform_option_def(key).unused(o); !why.empty())
      throw UsageError(deform_option_def(key).flag + why);
  check_combinations(o);
  if (contains(given, "ordering")) check_ordering(o);
  if (contains(given, "cg_tolerance")) o.solver_options.tolerance = o.cg_tolerance;
  return o;
}

std::string deform_options_markdown() {
  std::ostringstream md;
  std::string group = "-";
  const DeformOptions defaults;
  for (const DeformOptionDef& d : deform_option_defs()) {
    if (d.group != group) md << "\n**" << (d.group.empty() ? "Drag" : d.group) << "**\n\n";
    group = d.group;
    std::vector<std::string> quoted;
    for (const std::string& c : d.choices) quoted.push_back("`" + c + "`");
    const std::string values = d.is_switch                             ? "a switch"
                               : !d.range.empty()                      ? d.value_name + " in " + d.range
                               : !d.choices.empty() && d.choices.size() <= 8 ? fmt::format("{}", fmt::join(quoted, " \\| "))
                               : !d.choices.empty()                    ? "a name (see --help)"
                                                                       : d.value_name;
    const std::string def = d.get(defaults);
    md << fmt::format("- `{}` (`{}=`): {}{}. {}\n", d.flag, d.key, values,
                      def.empty() || d.is_switch ? "" : fmt::format(", default `{}`", def), d.help);
  }
  return md.str();
}

}  // namespace db
