#include "operators/energy_operator.h"

#include <Eigen/Dense>

#include "core/error.h"

namespace db {

EnergyKind parse_energy(const std::string& s) {
  if (s == "lap") return EnergyKind::Lap;
  if (s == "tf") return EnergyKind::Tf;
  throw InputError("unknown energy '" + s + "' (expected lap or tf)");
}

std::string to_string(EnergyKind k) { return k == EnergyKind::Lap ? "lap" : "tf"; }

EnergyOperator::EnergyOperator(const Points& V, const Faces& F, const Adjacency& adj, EnergyKind kind,
                               EnergyOptions opt)
    : V_(V), adj_(adj), kind_(kind), opt_(opt) {
  w_ = laplacian_weights(V, F, adj, opt.weights);
  delta_ = laplacian_coordinates(V, adj, w_);
}

void EnergyOperator::target(int i, double* out) const {
  if (kind_ == EnergyKind::Lap) {
    for (int c = 0; c < 3; ++c) out[c] = delta_(i, c);
  } else {
    out[0] = out[1] = out[2] = 0.0;
  }
}

void EnergyOperator::row(int i, std::vector<int>& cols, std::vector<double>& coeffs) const {
  const int m = adj_.degree(i) + 1;
  cols.clear();
  coeffs.clear();
  // Laplacian row first (scalar per column), with i placed among its sorted neighbours so cols ascend.
  {
    bool placed = false;
    for (int s = adj_.off[i]; s < adj_.off[i + 1]; ++s) {
      const int j = adj_.nbr[s];
      if (!placed && i < j) {
        cols.push_back(i);
        coeffs.push_back(1.0);
        placed = true;
      }
      cols.push_back(j);
      coeffs.push_back(-w_[s]);
    }
    if (!placed) {
      cols.push_back(i);
      coeffs.push_back(1.0);
    }
  }
  if (kind_ == EnergyKind::Lap) return;

  // TF: fit T_i = (s, h[, t]) to the 1-ring: minimize sum_k ||A_k (s,h,t) - v'_k||^2 (thesis eq. 2-11) with
  // A_k the 3 x 7 matrix of v_k below. (s,h,t) = N^-1 sum_k A_k^T v'_k with N = sum_k A_k^T A_k, and
  // T_i delta_i = G (s,h) with G = [delta, -[delta]x]. So the block of column k is
  // M_k = G (N^-1)[0:4, :] A_k^T, computed without forming the stacked 3m x 7 matrix.
  using Mat7 = Eigen::Matrix<double, 7, 7>;
  using Mat37 = Eigen::Matrix<double, 3, 7>;
  auto Ak = [&](int v) {
    const double x = V_(v, 0), y = V_(v, 1), z = V_(v, 2);
    Mat37 a;
    a << x, 0, z, -y, 1, 0, 0,  //
        y, -z, 0, x, 0, 1, 0,   //
        z, y, -x, 0, 0, 0, 1;
    return a;
  };
  Mat7 N = Mat7::Zero();
  for (int t = 0; t < m; ++t) {
    const Mat37 a = Ak(cols[t]);
    N.noalias() += a.transpose() * a;
  }
  const Vec3 dl = delta_.row(i).transpose();
  Eigen::Matrix<double, 3, 4> G;
  G << dl(0), 0, dl(2), -dl(1),  //
      dl(1), -dl(2), 0, dl(0),   //
      dl(2), dl(1), -dl(0), 0;   // G (s,h) = s*delta + h x delta, the same pattern as A_k's rows
  if (!opt_.tf_translation) {
    // Thesis eq. 2-12 (no translation): decouple the translation unknowns so they drop out of the fit.
    N.block<3, 4>(4, 0).setZero();
    N.block<4, 3>(0, 4).setZero();
    N.block<3, 3>(4, 4).setIdentity();
  }
  // W = G (N^-1)[0:4, :], i.e. W^T = N^-1 [G^T; 0] (N is symmetric): one 7x7 Cholesky and three solves
  // instead of an inverse (this fit is most of the TF build's arithmetic).
  Eigen::Matrix<double, 7, 3> Z = Eigen::Matrix<double, 7, 3>::Zero();
  Z.topRows<4>() = G.transpose();
  Mat37 W;
  Eigen::LLT<Mat7> llt(N);
  const auto d = llt.matrixLLT().diagonal();
  if (llt.info() == Eigen::Success && d.minCoeff() > 1e-6 * d.maxCoeff()) {  // pivots d^2 within 1e-12
    W = llt.solve(Z).transpose();
  } else {
    // A flat or collinear 1-ring leaves the fit underdetermined: take the minimum-norm transform.
    const Mat7 Ninv = Eigen::MatrixXd(N).completeOrthogonalDecomposition().pseudoInverse();
    W = G * Ninv.topRows<4>();
  }
  // Expand the scalar Laplacian row into 3x3 blocks: C_k = L_ik I - M_k.
  const std::size_t b2 = 9;
  coeffs.resize(b2 * m + m);  // scratch: the m Laplacian scalars move to the tail
  std::copy_backward(coeffs.begin(), coeffs.begin() + m, coeffs.end());
  const double* lap = coeffs.data() + b2 * m;
  for (int t = 0; t < m; ++t) {
    const Mat37 a = Ak(cols[t]);
    const Mat3 M = W * a.transpose();
    double* blk = coeffs.data() + b2 * t;
    const double l = lap[t];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) blk[3 * r + c] = (r == c ? l : 0.0) - M(r, c);
  }
  coeffs.resize(b2 * m);
}

}  // namespace db
