#pragma once
//! The linear systems a deformation factors, built as the deformer builds them (same normalization, constraint
//! classification, weights and energy) but without a solver: for `deformbench export-system` (Matrix Market out)
//! and the solver study's edit cells (`exp_solvers --edit`). The unknowns keep the mesh's vertex order (the
//! deformer's vertex-graph renumbering is left to the solver's ordering), so an exported matrix is the same
//! bytes whatever backend reads it.
//!
//! lap and tf: one system, K x_u = g0 - C x_h + W u, with the right-hand side of the edit's full drag (its handle
//! transform; an edit with per-vertex targets: their last frame), in normalized coordinates; TF's
//! --tf-scale normalized second pass is not part of it. lri: its two systems, "frames" (block 3) and
//! "positions" (block 1), matrices only (their right-hand sides follow from the frame solve of each frame).
#include <string>
#include <vector>

#include "edit/edit.h"
#include "mesh/mesh.h"
#include "methods/deform_options.h"
#include "solvers/base/types.h"
#include "systems/least_squares_system.h"

namespace db {

struct EditSystem {
  std::string name;  //!< "lap", "tf", "lri-frames", "lri-positions"
  int block = 1;     //!< unknowns per vertex block (the solvers' SolverOptions::block_size)
  SpMat K;           //!< upper triangle, block * #unknowns square
  DenseMat rhs;      //!< block * #unknowns x (3 for block 1, else 1); empty for lri
  double build_s = 0;  //!< the build of K (and its right-hand side), seconds
};

//! The method's systems with the structured build. \throw UsageError for options that do not go together
//! (resolve_options), InputError for a bad mesh or edit or a singular constraint set (as make_deformer).
std::vector<EditSystem> edit_systems(const Mesh& mesh, const Edit& edit, const DeformOptions& options);

//! lap and tf: the least-squares form of the same minimization (systems/least_squares_system.h), from the naive
//! build; A^T A is edit_systems' K, A^T b its rhs.
//! \throw UsageError for --method lri (no least-squares form here), else as edit_systems.
LeastSquaresSystem edit_least_squares(const Mesh& mesh, const Edit& edit, const DeformOptions& options);

}  // namespace db
