#pragma once
//! The least-squares form of a normal system's minimization (systems/normal_system.h), for a solver that
//! factors A itself (QR) instead of A^T A:
//!
//!   min ||A x_u - b||,   A = [A_u; w S],   b = [t - A_h x_h; w u]
//!
//! S selects the soft unknowns (one row per soft vertex and block component), t are the operator's targets.
//! A^T A is the system's K and A^T b the right-hand side g0 - C x_h + W u of K x_u. Built from the naive build,
//! the only one that keeps A_u^T, A_h and t (NormalSystem::At, Ah, targets). Used by `deformbench export-system
//! --least-squares` (methods/edit_system.h) and the solver study's least-squares cells.
#include "solvers/base/types.h"
#include "systems/normal_system.h"

namespace db {

struct LeastSquaresSystem {
  SpMat A;     //!< (rows of A_u + block * #soft) x block * #unknowns
  DenseMat b;  //!< rows of A x rhs_cols
};

//! \param sys a naive build (Build::Naive) of a LAP or TF energy
//! \param unk the unknowns `sys` was built for (its soft vertices and weight)
//! \param xh the hard vertices' values, block * #hard x rhs_cols in the solver layout; empty when there are none
//! \param u the soft vertices' targets, block * #soft x rhs_cols, in the order of unk.soft_vertices
//! \pre sys.At, sys.targets (and sys.Ah when xh is not empty) are set
LeastSquaresSystem least_squares_system(const NormalSystem& sys, const Unknowns& unk, const DenseMat& xh,
                                        const DenseMat& u);

}  // namespace db
