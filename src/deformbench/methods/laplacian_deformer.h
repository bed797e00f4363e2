#pragma once
//! LAP (uniform/cotan Laplacian editing, thesis eqs. 2-1..2-8) and TF (transform-fitted Laplacian editing,
//! Sorkine et al. 2004, thesis 2.3): one normal system each, factored once per edit (systems/min_quad_with_fixed.h).
//!
//! TF with normalized scale (DeformOptions::tf_scale normalized): TF's linearized similarities s I + [h]x grow and
//! shrink the surface under large rotations. A second pass keeps their rotations only (the two-pass remedy of
//! Lipman et al. 2004 and Sorkine et al. 2004): the rotation R_i of the T_i fitted to the TF result (the polar
//! factor of s I + [h]x), then min ||L x - R delta||^2 under the same constraints, the LAP system. That needs the
//! LAP factor beside TF's: TF's own normal matrix cannot serve, as its energy is blind to local similarities,
//! the scale included, which is exactly what the second pass must correct. The LAP matrix is scalar (one ninth
//! of TF's entries) and factored once per edit like TF's; each frame solves both.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "methods/deformer.h"
#include "methods/normalization.h"
#include "operators/energy_operator.h"
#include "systems/handle_response.h"

namespace db {

class LaplacianDeformer : public Deformer {
 public:
  LaplacianDeformer(const Mesh& mesh, const Edit& edit, EnergyKind kind, const DeformOptions& options);
  Points deform(const Mat4& handle_transform) override;
  Points deform_targets(const Points& targets) override;
  //! The rest solution and the responses to the 12 parameters of the handle's affine map (LAP: 4, shared by x, y,
  //! z), laid out per vertex, restored (systems/handle_response.h). With per-vertex targets (Edit::targets): the
  //! responses to each handle vertex's 3 coordinates (TF: 3h; LAP: h, shared by x, y, z), unless they would stream
  //! more than DeformOptions::handle_limit times the factor's bytes (then frames stay full: frame_mode_note).
  void precompute_handle_frames() override;

  //! The assembled system (for cross-checks between builds). Its K (or K_dense) is empty: the solver consumed
  //! it while factoring (LinearSolver::factorize_consuming, factorize_dense).
  const NormalSystem& system() const { return mqwf_.system(); }

 private:
  Edit edit_;
  std::vector<int> handle_vertices_;  // ascending: the order of per-vertex targets
  std::vector<int> handle_index_;     // per vertex: its row in a frame's targets, -1 off the handle
  double handle_limit_ = DeformOptions::kDefaultHandleLimit;
  EditSetup setup_;
  MinQuadWithFixed mqwf_;
  HandleResponse response_;  // FrameMode::Handle: every vertex's restored position, affine in the handle map
  DenseMat xh_, soft_, x_;  // per-frame buffers, reused
  // TF with normalized scale: the LAP operator (its rows and TF's 1-ring fit) and system of the second pass.
  std::unique_ptr<EnergyOperator> lap_op_;
  bool normalize_scale_ = false;
  MinQuadWithFixed rescale_;

  //! Orders the unknowns (structured builds) and builds the system; `vertex_ordering` is the ordering used
  //! ("" when the solver orders), `ordering_seconds` its time.
  NormalSystem build(const EnergyOperator& op, const DeformOptions& options, const std::string& solver,
                     SolverOptions& so, std::string& vertex_ordering, double& ordering_seconds);
  //! Whether this rank assembles only its share (DeformOptions::ranks > 1, the structured build).
  static bool rank_local(const DeformOptions& options);
  //! build() for a rank share: the same ordering on every rank (checked), then this rank's share.
  NormalSystem build_share(const EnergyOperator& op, const DeformOptions& options, const std::string& vertex_ordering,
                           double& ordering_seconds);
  //! xh_ and soft_ for a handle transform, or (targets non-null) the handle vertices' targets, in normalized
  //! coordinates.
  void constraint_values(const Mat4& T, const Points* targets = nullptr);
  //! Whether per-vertex responses of m parameters stay within handle_limit_ times the factor (else the note says
  //! why frames stay full).
  bool within_handle_limit(int m);
  //! Fast path: the hard and soft handle vertices are the constraints that move between frames.
  void set_varying();
  //! Builds and factors the second pass's LAP system on the unknowns of the first (TfScale::Normalized).
  void precompute_rescale(const Faces& F, const DeformOptions& options, const SolverOptions& so);
  //! The second pass: positions (normalized) from the TF result `Vn1`.
  Points rescale(const Points& Vn1);
  //! Normalized positions of all vertices from a solve's unknowns `x` and the hard values `xh` in layout `block`.
  Points positions(const DenseMat& x, const DenseMat& xh, int block) const;
  Points deform_handle(const Mat4& T);
  //! A handle-mode frame: streams the responses for the parameters theta into restored positions.
  Points stream(const DenseMat& theta);
  //! A full frame: the right-hand side from constraint_values as `set_values` sets them, the solve, the positions.
  Points deform_full(const std::function<void()>& set_values);
};

}  // namespace db
