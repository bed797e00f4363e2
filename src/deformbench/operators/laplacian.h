#pragma once
//! The discrete Laplacian in random-walk form (thesis eq. 2-1, 2-7): L(v_i) = v_i - sum_j w_ij v_j with
//! sum_j w_ij = 1 over the 1-ring, uniform (w_ij = 1/d_i) or cotangent weights normalized per row.
#include <string>
#include <vector>

#include "core/enum_text.h"
#include "solvers/base/types.h"
#include "mesh/mesh.h"

namespace db {

enum class Weights { Uniform, Cotan };
const EnumText<Weights>& enum_text(Weights);  //!< "uniform" | "cotan" (core/enum_text.h)

//! w_ij aligned with adj.nbr (entry off[i]+t is the weight of the t-th neighbour of i); rows sum to 1.
//! \throw InputError when a cotangent row sums to (almost) zero or is not finite (degenerate 1-ring).
std::vector<double> laplacian_weights(const Points& V, const Faces& F, const Adjacency& adj, Weights w);

//! delta = L V, #V by 3.
Points laplacian_coordinates(const Points& V, const Adjacency& adj, const std::vector<double>& w);

}  // namespace db
