#pragma once
//! Tutte's embedding of a disk patch: the boundary loop on the unit circle (by chord length, its first vertex at
//! angle 0, in the loop's order), every interior vertex at the average of its neighbours. Uniform weights give a
//! bijective map for any disk (Tutte's theorem: convex boundary, positive weights), where cotangent (harmonic)
//! weights can fold on obtuse triangles; and the map depends on the connectivity and the boundary's chord
//! lengths only, so two patches with the same connectivity and boundary map identically (what makes coating
//! transfer onto a surface's own smooth version exact). Solved as the minimum of the Dirichlet energy
//! sum_edges |u_i - u_j|^2 with the boundary fixed, through systems/min_quad_with_fixed.h.
#include "applications/disk_patch.h"
#include "solvers/base/types.h"
#include "systems/min_quad_with_fixed.h"

namespace db {

//! #V by 2 parameter positions.
using UV = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;

//! The Tutte embedding of `patch`. `report`, when given, receives the system's sizes and factor statistics.
//! \throw InputError for a boundary of zero length, SolverError from the factorization.
UV tutte_parameterization(const DiskPatch& patch, SystemReport* report = nullptr);

}  // namespace db
