#pragma once
//! LRI: linear rotation-invariant coordinates (Lipman, Sorkine, Levin, Cohen-Or 2005; thesis chapters 3-4).
//! The rest mesh is encoded by per-vertex frames F_i = [b1 b2 N] (operators/frames.h), the frame connection
//! R_ij = F_i^T F_j of every 1-ring edge and the discrete forms d_ij = F_i^T (x_j - x_i). An edit is decoded by
//! two linear least-squares systems, both built once per edit (structurally, from the adjacency) and factored
//! once; every frame costs two back-substitutions:
//!
//!  1. frames (eqs. 3-16, 3-17):  min sum_(i,j) || F'_j - F'_i R_ij ||^2, handle frames = R_h F_i (R_h the
//!     rotation of the handle transform; F_i with DeformOptions::lri_frame_control), fixed frames = F_i. Per world component c the unknown of vertex i is
//!     row c of F'_i, (b1[c], b2[c], N[c]): a 3#V x 3#V system (block size 3) with 3 right-hand sides (x, y, z).
//!     The solved frames are not orthonormal (least squares averages rotations); they are orthonormalized by
//!     Gram-Schmidt (b1 first) or the polar decomposition (DeformOptions::lri_orthonormalize).
//!  2. positions (eq. 3-18):  min sum_(i,j) || x'_j - x'_i - F'_i d_ij ||^2, handle positions = T x_i, fixed
//!     positions = x_i: a #V x #V system (block size 1) with 3 right-hand sides.
//!
//! Both sums run over directed edges (each undirected edge twice, as the thesis' sum_i d_i rows); all edges
//! weigh 1 (DeformOptions::weights is ignored: the thesis' LRI has no Laplacian weights). Hard constraints (the
//! default) eliminate handle and fixed vertices from both systems; soft constraints keep them as unknowns with
//! rows w^2 ||F'_i - target||^2 and w^2 ||x'_i - target||^2. Coordinates are normalized as for LAP / TF.
#include <memory>
#include <vector>

#include "methods/deformer.h"
#include "methods/normalization.h"
#include "operators/frames.h"
#include "operators/lri_rows.h"
#include "systems/handle_response.h"
#include "systems/lri_system.h"
#include "systems/min_quad_with_fixed.h"

namespace db {

class LriDeformer : public Deformer {
 public:
  //! \throw InputError dense build, an unanchored free component,
  //!        degenerate normals; SolverError failed factorization; BudgetError over options.memory_budget.
  LriDeformer(const Mesh& mesh, const Edit& edit, const DeformOptions& options);
  //! \throw SolverError non-finite result or a degenerate solved frame; InputError a singular handle transform.
  Points deform(const Mat4& handle_transform) override;
  //! The frame system's rest solution and its 3 responses to the handle rotation (systems/handle_response.h).
  void precompute_handle_frames() override;

  FrameStrategy strategy() const { return strategy_; }
  Orthonormalization orthonormalization() const { return ortho_; }
  //! Rest frames (#V, in normalized coordinates: frames are scale free), with the strategy's bookkeeping.
  const FrameField& rest_frames() const { return frames_; }
  //! Discrete forms of the rest mesh in normalized coordinates, aligned with the adjacency.
  const std::vector<Vec3>& forms() const { return forms_; }
  //! Last deform(): solved frames before orthonormalization (hard vertices: their targets), and after.
  const std::vector<Mat3>& solved_frames_raw() const { return raw_; }
  const std::vector<Mat3>& solved_frames() const { return solved_; }
  //! The two systems as built (their K is kept: factored, not consumed).
  const NormalSystem& frame_system() const { return frames_mqwf_.system(); }
  const NormalSystem& position_system() const { return positions_mqwf_.system(); }

 private:
  Edit edit_;
  FrameStrategy strategy_;
  Orthonormalization ortho_;
  bool uncoordinated_ = false;  //!< DeformOptions::lri_frame_control
  EditSetup setup_;
  FrameField frames_;
  std::vector<Vec3> forms_;
  MinQuadWithFixed frames_mqwf_, positions_mqwf_;
  //! FrameMode::Handle: every vertex's solved frame, affine in the handle rotation (3 responses shared by the
  //! world components x, y, z), rows 3v+k = column k of F'_v.
  HandleResponse frame_response_;
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> xf_all_;  // its output, per frame
  std::vector<Mat3> raw_, solved_;
  DenseMat xhf_, softf_, xf_, tpos_, xhp_, softp_, xp_;  // per-frame buffers, reused

  //! The frame system's right-hand side for the handle rotation Rh (normalized coordinates); returns its time.
  double frame_rhs(const Mat3& Rh);
  //! From the solved frames xf_: raw_, solved_ and the position system's right-hand side for the handle
  //! transform T; returns its time.
  double position_rhs(const Mat4& T);
  //! The solved frames xf_ (full) or xf_all_ (handle) for the handle rotation Rh; returns the seconds of rhs and
  //! solve, or of streaming the responses.
  void solve_frames(const Mat3& Rh, double& rhs_s, double& solve_s);
};

//! The `lri` branch of make_deformer.
std::unique_ptr<Deformer> make_lri_deformer(const Mesh& mesh, const Edit& edit, const DeformOptions& options);

}  // namespace db
