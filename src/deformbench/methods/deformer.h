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
#include "methods/deform_options.h"
#include "methods/normalization.h"
#include "mesh/mesh.h"
#include "operators/laplacian.h"
#include "solvers/linear_solver.h"
#include "systems/min_quad_with_fixed.h"
#include "systems/normal_system.h"

namespace db {

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

//! Checks the options (resolve_options: the caller may have resolved them already) and the constraint set, then
//! builds the method's systems. \throw UsageError options that do not go together, InputError a bad edit (e.g. a free component without any constraint: singular),
//!        SolverError failed factorization, BudgetError over memory_budget.
std::unique_ptr<Deformer> make_deformer(const Mesh& mesh, const Edit& edit, const DeformOptions& options);

//! What make_deformer checks of its input before building anything (edit_systems too): the mesh (validate_mesh,
//! non-manifold elements allowed), the edit (validate_edit), and, for lri and cotan weights, a manifold 1-ring
//! around every vertex (uniform lap and tf deform a non-manifold mesh as it is, with a warning on stderr).
//! \param options resolved (resolve_options). \throw InputError naming the first problem.
void check_deform_input(const Mesh& mesh, const Edit& edit, const DeformOptions& options);

//! Per vertex: how it enters the system under the given mode.
std::vector<Constraint> classify(const Edit& edit, ConstraintMode mode);

//! Throws InputError when the constraints leave some connected set of unknown vertices free to move at no cost
//! (the system would be singular there). Each set must hold or border a constrained (soft or hard) vertex: LAP's
//! energy is blind to translations. With `positions` (TF), among them three not on one line: TF's energy is
//! blind to the linearized similarities (s I + [h]x) v + t, which leave two points, or any points on one line,
//! in place while rotating about that line.
void check_every_component_anchored(const Adjacency& adj, const std::vector<Constraint>& kind,
                                    const Points* positions = nullptr);

//! What every system of an edit starts from (the deformers' and edit_systems'): the rest positions normalized
//! (DeformOptions::normalize), the mesh's 1-ring graph and the unknowns of the edit's constraints.
struct EditSetup {
  Normalization norm;
  Points Vn;  //!< normalized rest positions
  Adjacency adj;
  Unknowns unk;
  double seconds = 0;  //!< the graph, the constraints' check and the unknowns (the normalization not counted)
};

//! The edit's setup, its constraints checked to anchor every component (check_every_component_anchored; with
//! `tf_anchoring`, TF's check on the normalized positions). \param options resolved (resolve_options).
//! \throw InputError a bad scale (Normalization::fit) or a component left free.
EditSetup setup_edit(const Mesh& mesh, const Edit& edit, const DeformOptions& options, bool tf_anchoring);

}  // namespace db
