#pragma once
//! The two least-squares energies of LRI (thesis 3.3, eqs. 3-16..3-18), generated one directed 1-ring edge at a
//! time. Both have one row block per directed edge (i, j) that touches only its two end vertices:
//!
//!   E(x) = sum_i sum_{j in N(i)} || P_ij x_i + Q_ij x_j - t_ij ||^2
//!
//! x_i holds b scalars per vertex (b = block size); every scalar has 3 right-hand-side columns that decouple
//! (the x, y, z world components). P_ij and Q_ij are b x b blocks.
//!  - frames (eq. 3-17, F_j = F_i R_ij): per world component c, x_i = (b1_i[c], b2_i[c], N_i[c]), b = 3,
//!    P_ij = -R_ij^T, Q_ij = I, t_ij = 0.
//!  - positions (eq. 3-18): x_i = the position, b = 1, P_ij = -1, Q_ij = 1, t_ij = F'_i d_ij (solved frame
//!    times the discrete form), new every frame.
//! Every edge weighs 1 (the thesis' LRI has no Laplacian weights). systems/lri_system.h forms the normal
//! equations from these rows.
#include <functional>
#include <vector>

#include "solvers/base/types.h"
#include "mesh/mesh.h"

namespace db {

//! Fills the b x b row-major blocks P_ij (coefficient of x_i) and Q_ij (of x_j) of directed edge (i, j);
//! `slot` is the edge's index in adj.nbr.
using EdgeBlocks = std::function<void(int i, int j, int slot, double* P, double* Q)>;

//! The rows of an edge energy: its block size and the blocks of every directed edge.
struct EdgeRows {
  int block = 1;
  EdgeBlocks blocks;
};

//! Frame energy: residual u_j - R_ij^T u_i of one world component u of [b1 b2 N], R_ij = F_i^T F_j.
//! `F` (the rest frames) is held by reference and must outlive the result.
EdgeRows lri_frame_rows(const std::vector<Mat3>& F);

//! Position energy: residual x_j - x_i - t_ij.
EdgeRows lri_position_rows();

//! Targets of the position energy, t_ij = F'_i d_ij: row `slot` of `t` (#directed edges x 3) for the directed
//! edge at adj.nbr[slot]. `frames`: the solved frames F'; `forms`: the rest discrete forms (operators/frames.h).
void lri_position_targets(const Adjacency& adj, const std::vector<Mat3>& frames, const std::vector<Vec3>& forms,
                          DenseMat& t);

}  // namespace db
