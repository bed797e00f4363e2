#pragma once
//! Deformation methods behind one precompute / per-frame interface (libigl's precompute/solve split):
//! the constructor builds, analyzes and factorizes once per edit; deform() runs every frame.
#include <cstddef>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "solvers/base/types.h"
#include "edit/edit.h"
#include "mesh/mesh.h"
#include "operators/laplacian.h"
#include "solvers/linear_solver.h"
#include "systems/min_quad_with_fixed.h"
#include "systems/normal_system.h"

namespace db {

enum class ConstraintMode { Hard, Soft };
ConstraintMode parse_constraints(const std::string& s);  //!< "hard" | "soft"
std::string to_string(ConstraintMode m);

//! Full: every frame forms its right-hand side and solves (the thesis' frame). Handle: the solution is affine in
//! the handle transform, so the responses are solved for once after the factorization (systems/handle_response.h)
//! and a frame only streams them (LRI: its frame system; the position solve stays per frame). The same holds for
//! per-vertex targets (Edit::targets; lap and tf), with responses that grow with the handle.
enum class FrameMode { Full, Handle };
FrameMode parse_frame_mode(const std::string& s);  //!< "full" | "handle"
std::string to_string(FrameMode m);

struct DeformOptions {
  std::string method = "lap";  //!< "lap", "tf" or "lri" (see make_deformer)
  Weights weights = Weights::Uniform;
  bool tf_translation = true;  //!< TF: fit t as well (false: thesis eq. 2-12)
  //! TF: false ("free") keeps the linearized similarities T_i as fitted, scale included; true ("normalized")
  //! keeps only their rotations: a second pass turns each rest delta_i by the rotation part of the T_i fitted to
  //! the TF result and solves the LAP system to those (methods/laplacian_deformer.h).
  bool tf_normalize_scale = false;
  //! Hard: handle and fixed vertices are eliminated. Soft: they stay unknowns with weighted rows w^2 ||v - u||^2
  //! (thesis eq. 2-4).
  ConstraintMode constraints = ConstraintMode::Hard;
  double soft_weight = 1.0;
  Build build = Build::Structured;
  //! Linear-solver backend (solvers/, `deformbench solvers`). Empty: the build's default, multifrontal for the
  //! sparse builds and dense_llt for the dense one (systems/min_quad_with_fixed.h, resolve_solver). The dense
  //! build takes only dense backends (InputError otherwise) and orders nothing (solver_options.ordering does not
  //! reach them); the sparse builds take any backend, dense ones included (they expand K: small systems only).
  std::string solver;
  SolverOptions solver_options;
  bool normalize = true;             //!< center and scale before building (see normalization.h)
  std::size_t memory_budget = 0;     //!< bytes; 0 = unlimited. Checked on predictions before allocating.
  // LRI only (issue 5): frame strategy and orthonormalization; ignored by lap and tf.
  std::string lri_frames = "first";
  std::string lri_orthonormalize = "gram_schmidt";
  unsigned lri_seed = 1;
  //! LRI: false (the method) constrains the handle's frames to the rotation of the transform that moves its
  //! positions; true leaves them at rest while the positions move - the uncoordinated control of the thesis'
  //! fig. 3-4, offered to show what coordination buys.
  bool lri_uncoordinated = false;
  FrameMode frame_mode = FrameMode::Full;
  //! Handle mode with per-vertex targets (Edit::targets): the responses grow with the handle (3h columns), so a
  //! handle frame stops paying once it streams more than this many times the factor's bytes; beyond, the deformer
  //! keeps full frames and says so (Deformer::frame_mode_note). The default is measured (results/handle_drags.md).
  double handle_limit = kDefaultHandleLimit;
  static constexpr double kDefaultHandleLimit = 1.0;
  //! This process is rank `rank` of `ranks` > 1 (a launcher's; solver "mumps"): lap and tf with the structured
  //! build assemble only this rank's share of their systems (build_structured_share; rank-local assembly) and the
  //! solver sums the shares. The other methods and builds assemble the whole system on every rank (the solver
  //! then passes each rank's columns of it).
  int rank = 0, ranks = 1;
};

struct PhaseTimes {
  double build = 0, analyze = 0, factorize = 0;  //!< seconds, once per edit
  double precompute = 0;  //!< seconds, once per edit after init: the handle responses (FrameMode::Handle), else 0
  double rhs = 0, solve = 0, write = 0;          //!< seconds, last frame
  double response = 0;  //!< seconds, last frame: streaming the handle responses (FrameMode::Handle), else 0
  double orthonormalize = 0;  //!< LRI, last frame: the part of rhs that orthonormalizes the solved frames
  double init() const { return build + analyze + factorize; }
  double frame() const { return rhs + solve + write + response; }
};

class Deformer {
 public:
  virtual ~Deformer() = default;
  //! Deformed positions (#V by 3) for the given handle transform (fixed vertices stay put).
  //! \throw SolverError when the result is not finite.
  virtual Points deform(const Mat4& handle_transform) = 0;
  //! Deformed positions for a general drag: `targets` (h by 3, original coordinates) are the handle vertices'
  //! positions, in ascending vertex index (one frame of Edit::targets). lap and tf only: LRI's frames follow one
  //! handle rotation, which per-vertex targets do not give (InputError).
  virtual Points deform_targets(const Points& targets);
  const PhaseTimes& times() const { return times_; }
  const std::vector<SystemReport>& systems() const { return systems_; }
  std::size_t matrix_bytes() const;  //!< bytes of the system matrices handed to the solvers
  std::size_t factor_bytes() const;
  FrameMode frame_mode() const { return frame_mode_; }
  //! Switches to FrameMode::Handle on the factored systems (what DeformOptions::frame_mode = Handle does after
  //! the factorization): a deformer can measure full frames, then handle frames, from one init. Sets
  //! times().precompute. \throw SolverError for a failed or non-finite solve.
  virtual void precompute_handle_frames() = 0;
  //! FrameMode::Handle: bytes of the stored responses one frame streams (HandleResponse::bytes), else 0.
  std::size_t response_bytes() const { return response_bytes_; }
  //! Why handle mode was asked for but full frames run (the per-vertex responses above DeformOptions::handle_limit
  //! times the factor), else empty.
  const std::string& frame_mode_note() const { return frame_mode_note_; }

 protected:
  PhaseTimes times_;
  FrameMode frame_mode_ = FrameMode::Full;
  std::size_t response_bytes_ = 0;
  std::string frame_mode_note_;
  std::vector<SystemReport> systems_;
};

//! Validates mesh-independent options and the constraint set, then builds the method's systems.
//! \throw InputError bad options or edit (e.g. a free component without any constraint: singular),
//!        SolverError failed factorization, BudgetError over memory_budget.
std::unique_ptr<Deformer> make_deformer(const Mesh& mesh, const Edit& edit, const DeformOptions& options);

//! Per vertex: how it enters the system under the given mode.
std::vector<Constraint> classify(const Edit& edit, ConstraintMode mode);

//! Throws InputError when the constraints leave some connected set of unknown vertices free to move at no cost
//! (the system would be singular there). Each set must hold or border a constrained (soft or hard) vertex: LAP's
//! energy is blind to translations. With `positions` (TF), among them three not on one line: TF's energy is
//! blind to the linearized similarities (s I + [h]x) v + t, which leave two points, or any points on one line,
//! in place while rotating about that line.
void check_every_component_anchored(const Adjacency& adj, const std::vector<Constraint>& kind,
                                    const Points* positions = nullptr);

}  // namespace db
