#pragma once
//! LAP (uniform/cotan Laplacian editing, thesis eqs. 2-1..2-8) and TF (transform-fitted Laplacian editing,
//! Sorkine et al. 2004, thesis 2.3): one normal system each, factored once per edit.
#include <memory>
#include <vector>

#include <Eigen/Cholesky>

#include "methods/deformer.h"
#include "methods/normalization.h"
#include "operators/energy_operator.h"

namespace db {

class LaplacianDeformer : public Deformer {
 public:
  LaplacianDeformer(const Mesh& mesh, const Edit& edit, EnergyKind kind, const DeformOptions& options);
  Points deform(const Mat4& handle_transform) override;

  //! The assembled system (for cross-checks between builds). With a sparse build its K is empty: the solver
  //! consumed it while factoring (LinearSolver::factorize_consuming).
  const NormalSystem& system() const { return sys_; }

 private:
  Edit edit_;
  Normalization norm_;
  Points Vn_;  // normalized rest positions
  Unknowns unk_;
  NormalSystem sys_;
  std::unique_ptr<LinearSolver> solver_;      // sparse builds
  std::unique_ptr<Eigen::LLT<DenseMat>> llt_;  // dense build: dense Cholesky
  DenseMat xh_, rhs_, x_;                      // per-frame buffers, reused
  std::vector<int> frame_rows_;
  bool base_rhs_set_ = false;  // the solver holds the rest-pose right-hand side (first frame sets it)

  //! rhs_ and xh_ for a handle transform in normalized coordinates.
  void assemble_rhs(const Mat4& T);
  //! Solver rows whose right-hand side depends on the handle transform: the soft handle vertices' rows and the
  //! rows coupled to hard handle vertices through C. Every other row is the same in every frame.
  std::vector<int> handle_rows() const;
};

}  // namespace db
