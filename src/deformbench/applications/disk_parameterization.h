#pragma once
//! Maps of a disk patch onto the unit disk: the boundary loop on the unit circle (by chord length, its first
//! vertex at angle 0, in the loop's order), every interior vertex at a weighted average of its neighbours,
//! sum_j w_ij (u_i - u_j) = 0. The weights choose the map:
//!  - uniform (Tutte): w_ij = 1. Bijective for any disk (Tutte's theorem: convex boundary, positive weights) and
//!    a function of the connectivity and the boundary's chord lengths only; but it ignores the geometry, so an
//!    irregular patch's dense parts spread over the disk while its sparse parts shrink.
//!  - mean value (Floater 2003): w_ij = (tan(a_ij / 2) + tan(b_ij / 2)) / |p_i - p_j|, a and b the angles at i
//!    beside edge ij. Positive, so still bijective; reproduces a planar patch's own shape where its boundary
//!    allows, so vertex density on the disk follows the density on the surface. Not symmetric: solved by LU.
//!  - cotangent (harmonic, Pinkall-Polthier / Eck et al.): w_ij = (cot a + cot b) / 2 over the angles opposite
//!    edge ij; the discrete conformal map for a fixed boundary, but weights go negative on obtuse triangles and
//!    the map can fold there.
//! All depend on the patch alone, so two patches with the same shape, connectivity and boundary map identically
//! (what makes a surface's own coating go back onto its own smooth version exactly - for mean value and cotangent
//! weights only when both are computed on the same positions, as coating transfer does: see coating_transfer.h).
//! Uniform and cotangent systems (symmetric, positive definite with the boundary fixed) go through
//! systems/min_quad_with_fixed.h; the mean-value system, not symmetric, through Eigen's sparse LU. Written here
//! rather than taken from CGAL's Surface_mesh_parameterization, whose mean-value and discrete-conformal
//! parameterizers with a circular arc-length border give the same maps (tests/applications_test.cpp compares
//! them, to rounding): each map is its weights only, the patch needs no conversion to a CGAL halfedge mesh, and
//! the symmetric ones share the project's solve path.
//! LSCM (free boundary) is not offered: it gives each patch a domain of its own shape, and coating transfer
//! needs both on one domain.
#include "applications/disk_patch.h"
#include "core/enum_text.h"
#include "solvers/base/types.h"
#include "systems/min_quad_with_fixed.h"

namespace db {

//! #V by 2 parameter positions.
using UV = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;

enum class DiskMap { Uniform, MeanValue, Cotangent };
const EnumText<DiskMap>& enum_text(DiskMap);  //!< "uniform" | "mean-value" | "cotangent"

//! The map of `patch` onto the unit disk with `weights`. `report`, when given, receives the system's sizes and
//! factor statistics (symmetric systems only). \throw InputError for a boundary of zero length or weights that
//! are not finite (a degenerate triangle), SolverError from the factorization.
UV disk_parameterization(const DiskPatch& patch, DiskMap weights, SystemReport* report = nullptr);

//! The map's system over the interior vertices (in the patch's order): row i is sum_j w_ij (u_i - u_j), the
//! boundary's columns left out. What tests need for its condition number. \throw as disk_parameterization.
Eigen::SparseMatrix<double> disk_map_system(const DiskPatch& patch, DiskMap weights);

//! The Tutte embedding of `patch` (uniform weights).
inline UV tutte_parameterization(const DiskPatch& patch, SystemReport* report = nullptr) {
  return disk_parameterization(patch, DiskMap::Uniform, report);
}

}  // namespace db
