#pragma once
//! Normal equations of the two LRI least-squares systems (thesis 3.3, eqs. 3-16..3-18). Both energies have
//! one row block per directed 1-ring edge (i, j) that touches only its two end vertices:
//!
//!   E(x) = sum_i sum_{j in N(i)} || P_ij x_i + Q_ij x_j - t_ij ||^2  +  w^2 sum_{soft s} || x_s - u_s ||^2
//!
//! x_i holds b scalars per vertex (b = block size); every scalar has `cols` right-hand-side columns that
//! decouple (the x, y, z world components). P_ij and Q_ij are b x b blocks.
//!  - frames (eq. 3-17, F_j = F_i R_ij): per world component c, x_i = (b1_i[c], b2_i[c], N_i[c]), b = 3,
//!    P_ij = -R_ij^T, Q_ij = I, t_ij = 0; a 3#V x 3#V system with 3 columns (x, y, z).
//!  - positions (eq. 3-18): x_i = the position, b = 1, P_ij = -1, Q_ij = 1, t_ij = F'_i d_ij (solved frame
//!    times the discrete form); a #V x #V system with 3 columns.
//! With the unknown / hard split of Unknowns (systems/normal_system.h):
//!
//!   K = A_u^T A_u + W   upper triangle, b#unknowns square; block pattern = the 1-ring (no 2-ring fill)
//!   C = A_u^T A_h       b#unknowns x b#hard
//!   per frame:  K x_u = A_u^T t - C x_h + W u
//!
//! The structured build lays out K's pattern from the adjacency and accumulates P^T P, P^T Q, Q^T Q edge by
//! edge: A is never stored. The naive build forms A_u, A_h from triplets and multiplies (for cross-checks).
#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "core/types.h"
#include "mesh/mesh.h"
#include "systems/normal_system.h"

namespace db {

//! Fills the b x b row-major blocks P_ij (coefficient of x_i) and Q_ij (of x_j) of directed edge (i, j);
//! `slot` is the edge's index in adj.nbr.
using EdgeBlocks = std::function<void(int i, int j, int slot, double* P, double* Q)>;

struct EdgeSystem {
  // Moves swap the sparse matrices (Eigen 3.4's SparseMatrix has no move operations; see NormalSystem).
  EdgeSystem() = default;
  EdgeSystem(const EdgeSystem&) = default;
  EdgeSystem& operator=(const EdgeSystem&) = default;
  EdgeSystem(EdgeSystem&& o) noexcept { *this = std::move(o); }
  EdgeSystem& operator=(EdgeSystem&& o) noexcept {
    build = o.build;
    block = o.block;
    K.swap(o.K);
    C.swap(o.C);
    held_bytes = std::move(o.held_bytes);
    return *this;
  }

  Build build = Build::Structured;
  int block = 1;
  SpMat K;  //!< upper triangle of A_u^T A_u + W, (b #unknowns)^2
  SpMat C;  //!< A_u^T A_h, b #unknowns x b #hard
  std::vector<std::pair<std::string, std::size_t>> held_bytes;  //!< matrices held at the build's peak
};

//! \throw InputError for Build::Dense (not offered for LRI) or a classification that does not match adj;
//!        BudgetError when byte_budget > 0 and the predicted bytes exceed it.
EdgeSystem build_edge_system(const Adjacency& adj, const Unknowns& unk, int block, const EdgeBlocks& blocks,
                             Build build, std::size_t byte_budget = 0);

//! Predicted peak bytes of a build (from the adjacency only).
std::size_t predict_edge_system_bytes(const Adjacency& adj, const Unknowns& unk, int block, Build build);

//! g += A_u^T t: `t` holds one b x cols block per directed edge, rows b*slot .. b*slot+b-1 (slot = index in
//! adj.nbr); g is b#unknowns x cols. Edges with both ends hard are skipped (they do not enter K).
void add_At_targets(const Adjacency& adj, const Unknowns& unk, int block, const EdgeBlocks& blocks, const DenseMat& t,
                    DenseMat& g);

}  // namespace db
