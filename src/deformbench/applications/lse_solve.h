#pragma once
//! The LSE reconstruction the applications share: positions whose uniform Laplacian coordinates match given
//! ones in least squares, with some vertices fixed and others pulled softly towards targets (Sorkine et al.
//! 2004, eq. 5; Sorkine and Cohen-Or 2004's least-squares meshes for the smoothing):
//!
//!   min sum_i |L(x)_i - delta_i|^2 + w^2 sum_{soft s} |x_s - t_s|^2,   x_h = t_h on the hard vertices,
//!
//! the sum over every row that touches an unknown, as the deformers' LAP energy. The LAP operator's structured
//! build gives K and C (they do not depend on delta); g0 = A_u^T delta is formed here from the operator's rows;
//! systems/min_quad_with_fixed.h factors and solves.
#include <vector>

#include "solvers/base/types.h"
#include "mesh/mesh.h"
#include "systems/min_quad_with_fixed.h"

namespace db {

struct LseReport {
  SystemReport system;  //!< n = 0 when nothing was left to solve for
  double build_s = 0, analyze_s = 0, factorize_s = 0, solve_s = 0;
};

//! x for per-vertex `kinds`, Laplacian coordinates `delta` (#V by 3) and `targets` (#V by 3: the hard values and
//! the soft targets; free vertices' rows unused). \throw InputError for mismatched sizes or a free set of
//! vertices touching no constraint (singular), SolverError from the solve.
Points solve_lse(const Mesh& mesh, const std::vector<Constraint>& kinds, double soft_weight, const Points& delta,
                 const Points& targets, LseReport* report = nullptr);

//! Uniform Laplacian coordinates L(V) (operators/laplacian.h) of `mesh`.
Points uniform_delta(const Mesh& mesh, const Adjacency& adj);

}  // namespace db
