#pragma once
//! LAP (uniform/cotan Laplacian editing, thesis eqs. 2-1..2-8) and TF (transform-fitted Laplacian editing,
//! Sorkine et al. 2004, thesis 2.3): one normal system each, factored once per edit (systems/min_quad_with_fixed.h).
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
  //! The rest solution and the responses to the 12 parameters of the handle's affine map (LAP: 4, shared by x, y,
  //! z), laid out per vertex, restored (systems/handle_response.h).
  void precompute_handle_frames() override;

  //! The assembled system (for cross-checks between builds). Its K (or K_dense) is empty: the solver consumed
  //! it while factoring (LinearSolver::factorize_consuming, factorize_dense).
  const NormalSystem& system() const { return mqwf_.system(); }

 private:
  Edit edit_;
  Normalization norm_;
  Points Vn_;  // normalized rest positions
  Unknowns unk_;
  MinQuadWithFixed mqwf_;
  HandleResponse response_;  // FrameMode::Handle: every vertex's restored position, affine in the handle map
  DenseMat xh_, soft_, x_;  // per-frame buffers, reused

  //! Orders the unknowns (structured builds) and builds the system; `vertex_ordering` is the ordering used
  //! ("" when the solver orders), `ordering_seconds` its time.
  NormalSystem build(const EnergyOperator& op, const DeformOptions& options, const std::string& solver,
                     SolverOptions& so, std::string& vertex_ordering, double& ordering_seconds);
  //! xh_ and soft_ for a handle transform in normalized coordinates.
  void constraint_values(const Mat4& T);
  //! Fast path: the hard and soft handle vertices are the constraints that move between frames.
  void set_varying();
  Points deform_handle(const Mat4& T);
};

}  // namespace db
