#pragma once
//! The least-squares operator A of a linear Laplacian-type energy ||A V' - b||^2, generated one row block
//! at a time from the mesh adjacency, so builders can form A^T A without ever storing A.
//!
//! Row block i couples vertex i with its 1-ring: A_i V' = sum_{k in {i} u N(i)} C_ik v'_k.
//!  - LAP (thesis eq. 2-1..2-8): C_ik scalar (1 for k = i, -w_ik otherwise), the same for x, y and z;
//!    target b_i = delta_i. Block size 1, three right-hand-side columns (x, y, z).
//!  - TF (Sorkine et al. 2004, thesis 2.3): A_i V' = L(v'_i) - T_i(V') delta_i where T_i = s I + [h]x is the
//!    similarity fitted to the 1-ring of i in least squares (eq. 2-11), a linear function of V'.
//!    C_ik = L_ik I - M_ik, 3x3 blocks; target 0. Block size 3 (interleaved x,y,z), one column.
#include <string>
#include <vector>

#include "core/enum_text.h"
#include "solvers/base/types.h"
#include "mesh/mesh.h"
#include "operators/laplacian.h"

namespace db {

enum class EnergyKind { Lap, Tf };

struct EnergyOptions {
  Weights weights = Weights::Uniform;
  //! TF only: fit a translation as well (Sorkine 2004, 7 unknowns). false = thesis eq. 2-12 (4 unknowns).
  bool tf_translation = true;
};

class EnergyOperator {
 public:
  //! V: #V by 3 positions (already normalized by the caller); adj: 1-ring adjacency of the same mesh.
  EnergyOperator(const Points& V, const Faces& F, const Adjacency& adj, EnergyKind kind, EnergyOptions opt);

  EnergyKind kind() const { return kind_; }
  int block() const { return kind_ == EnergyKind::Lap ? 1 : 3; }
  int rhs_cols() const { return kind_ == EnergyKind::Lap ? 3 : 1; }
  int num_vertices() const { return adj_.num_vertices(); }
  const Adjacency& adjacency() const { return adj_; }

  //! Row block i: cols = {i} u N(i) in ascending order; coeffs = one block*block row-major block per column.
  void row(int i, std::vector<int>& cols, std::vector<double>& coeffs) const;
  //! Target of row block i as block x rhs_cols values (row-major): delta_i for LAP, zeros for TF.
  void target(int i, double* out) const;
  //! The rest Laplacian coordinates delta (#V by 3), with this operator's weights.
  const Points& delta() const { return delta_; }
  //! The rotation part of T_i = s I + [h]x fitted to the 1-ring of i in `deformed` (#V by 3, the coordinates of
  //! V): the rotation by atan2(|h|, s) about h, so that T_i = R_i S_i with S_i symmetric and eigenvalues
  //! |(s, h)|, |(s, h)| and s (the polar decomposition where s > 0; defined up to 180 degrees). Identity for h = 0.
  //! Any kind: the fit is TF's (with or without translation, as the options say).
  Mat3 fitted_rotation(int i, const Points& deformed) const;

 private:
  const Points& V_;
  const Adjacency& adj_;
  EnergyKind kind_;
  EnergyOptions opt_;
  std::vector<double> w_;  // Laplacian weights aligned with adj_.nbr
  Points delta_;
};

//! "lap" | "tf" (core/enum_text.h).
const EnumText<EnergyKind>& enum_text(EnergyKind);

}  // namespace db
