#pragma once
//! The options of one deformation, typed, and the one table that describes them (deform_option_defs): key, flag,
//! values, default, help and the rule that says when an option is not used. The command line (`deformbench
//! deform`), the key=value parser of cell specs, experiment configs and benchmarks (set_deform_option), the check
//! (resolve_options) and the reference listing (deform_options_markdown, docs/cli.md) all read that table.
//!
//! Adding an option: a field in DeformOptions (where the methods read it) and a row in deform_options.cpp's table.
#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "core/enum_text.h"
#include "operators/frames.h"
#include "operators/laplacian.h"
#include "solvers/linear_solver.h"
#include "systems/normal_system.h"

namespace db {

enum class Method { Lap, Tf, Lri };
const EnumText<Method>& enum_text(Method);  //!< "lap" | "tf" | "lri"

//! Hard: handle and fixed vertices are eliminated. Soft: they stay unknowns with weighted rows w^2 ||v - u||^2
//! (thesis eq. 2-4).
enum class ConstraintMode { Hard, Soft };
const EnumText<ConstraintMode>& enum_text(ConstraintMode);  //!< "hard" | "soft"

//! Full: every frame forms its right-hand side and solves (the thesis' frame). Handle: the solution is affine in
//! the handle transform, so the responses are solved for once after the factorization (systems/handle_response.h)
//! and a frame only streams them (LRI: its frame system; the position solve stays per frame). The same holds for
//! per-vertex targets (Edit::targets; lap and tf), with responses that grow with the handle.
enum class FrameMode { Full, Handle };
const EnumText<FrameMode>& enum_text(FrameMode);  //!< "full" | "handle"

//! TF: Free keeps the linearized similarities T_i as fitted, scale included; Normalized keeps only their
//! rotations: a second pass turns each rest delta_i by the rotation part of the T_i fitted to the TF result and
//! solves the LAP system to those (methods/laplacian_deformer.h).
enum class TfScale { Free, Normalized };
const EnumText<TfScale>& enum_text(TfScale);  //!< "free" | "normalized"

//! LRI: Coordinated (the method) constrains the handle's frames to the rotation of the transform that moves its
//! positions; Uncoordinated leaves them at rest while the positions move - the thesis' fig. 3-4, offered to show
//! what coordination buys.
enum class FrameControl { Coordinated, Uncoordinated };
const EnumText<FrameControl>& enum_text(FrameControl);  //!< "coordinated" | "uncoordinated"

//! Double, or Mixed: the factor stored in single precision (kMixedBackend), each solve refined by CG in double.
enum class Precision { Double, Mixed };
const EnumText<Precision>& enum_text(Precision);  //!< "double" | "mixed"

//! The mixed-precision counterpart of the default sparse backend.
inline constexpr const char* kMixedBackend = "multifrontal_mixed";
//! Whether the backend refines its solves (DeformOptions::refine_*): the mixed-precision one and the double ones
//! refined alike.
bool refines(const std::string& backend);

struct DeformOptions {
  Method method = Method::Lap;
  Weights weights = Weights::Uniform;  //!< lap and tf (LRI's systems have no Laplacian weights)
  bool tf_translation = true;          //!< TF: fit t as well (false: thesis eq. 2-12)
  TfScale tf_scale = TfScale::Free;
  ConstraintMode constraints = ConstraintMode::Hard;
  double soft_weight = 1.0;  //!< w of the soft rows (ConstraintMode::Soft)
  bool normalize = true;     //!< center and scale before building (see normalization.h)
  FrameStrategy lri_frames = FrameStrategy::First;
  Orthonormalization lri_orthonormalize = Orthonormalization::GramSchmidt;
  unsigned lri_seed = 1;  //!< FrameStrategy::Random
  FrameControl lri_frame_control = FrameControl::Coordinated;
  Build build = Build::Structured;
  //! Linear-solver backend (solvers/, `deformbench solvers`). Empty: the build's default, multifrontal for the
  //! sparse builds and dense_llt for the dense one (resolve_options names it; make_deformer resolves a copy).
  //! The dense build takes only dense backends and orders nothing; the sparse builds take any backend, dense
  //! ones included (they expand K: small systems only).
  std::string solver;
  //! Ordering ("default": the backend's own, or the vertex graph's with the structured lap/tf build), the
  //! out-of-core directory and, for refining backends, the refinement's tolerance and iteration cap.
  SolverOptions solver_options;
  Precision precision = Precision::Double;
  //! Iterative backends (cg_jacobi, cg_ichol): the relative residual each solve must reach (resolve_options
  //! hands it to the backend when given).
  double cg_tolerance = 1e-10;
  std::size_t memory_budget = 0;      //!< bytes; 0 = unlimited. Checked on predictions before allocating.
  FrameMode frame_mode = FrameMode::Full;
  //! Handle mode with per-vertex targets (Edit::targets): the responses grow with the handle (3h columns), so a
  //! handle frame stops paying once it streams more than this many times the factor's bytes; beyond, the deformer
  //! keeps full frames and says so (Deformer::frame_mode_note). The default is measured (results/records/2026-11-24-handle-frames/).
  double handle_limit = kDefaultHandleLimit;
  static constexpr double kDefaultHandleLimit = 1.0;
  //! This process is rank `rank` of `ranks` > 1 (a launcher's; solver "mumps"): lap and tf with the structured
  //! build assemble only this rank's share of their systems (build_structured_share; rank-local assembly) and the
  //! solver sums the shares. The other methods and builds assemble the whole system on every rank.
  int rank = 0, ranks = 1;
};

//! One option: what the command line, the key=value parser, the check and the docs know of it.
struct DeformOptionDef {
  std::string key;         //!< spec / config key, "lri_frames"
  std::string flag;        //!< the command line's, "--lri-frames"
  std::string group;       //!< help section
  std::string value_name;  //!< "W", "N", ...; empty for a choice or a switch
  std::string help;
  std::vector<std::string> choices;  //!< the values it takes, when they are a list
  std::string range;                 //!< "[1e-08, 1e+08]" for a number, else empty
  bool is_switch = false;            //!< a flag without a value (key=value: 1 or 0)
  //! Checks `text` as the command line does (a number converted in place: "1e3" -> "1000") and returns why it is
  //! refused, or "" (CLI::Validator's shape).
  std::function<std::string(std::string& text)> check;
  //! Stores a checked value.
  std::function<void(DeformOptions&, const std::string& text)> set;
  //! The value as text ("" for none): the default, with DeformOptions{}.
  std::function<std::string(const DeformOptions&)> get;
  //! Why the option does nothing with these (resolved) options, or "" when it is used: given, it is refused.
  std::function<std::string(const DeformOptions&)> unused;
};

//! The table, in help order.
const std::vector<DeformOptionDef>& deform_option_defs();
//! The row of `key`. \throw UsageError naming the key for an unknown one.
const DeformOptionDef& deform_option_def(const std::string& key);

//! Sets one option from text (cell specs, configs, benchmark names). \throw UsageError "FLAG: why" for an unknown
//! key or a value out of range.
void set_deform_option(DeformOptions& o, const std::string& key, const std::string& text);
//! Every option whose value differs from `base`'s as key=value pairs (in table order): what a spec writes.
std::vector<std::pair<std::string, std::string>> deform_option_items(const DeformOptions& o,
                                                                    const DeformOptions& base = {});

//! The options checked together and the solver resolved, once, before any mesh is read: the backend named (the
//! build's default, or kMixedBackend for Precision::Mixed). `given`: the keys set explicitly (command line,
//! spec), each refused when the others leave it unused. make_deformer calls it too (library callers), with none.
//! \throw UsageError for a value out of range or options that do not go together, naming them by their flags.
DeformOptions resolve_options(DeformOptions o, const std::vector<std::string>& given = {});

//! The table as a Markdown list for the reference (docs/cli.md; `deformbench deform-options`).
std::string deform_options_markdown();

}  // namespace db
