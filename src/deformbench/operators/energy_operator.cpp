#include "operators/energy_operator.h"

#include <cmath>
#include <vector>

#include <Eigen/Dense>

#include "solvers/base/error.h"

namespace db {

namespace {
using Mat7 = Eigen::Matrix<double, 7, 7>;
using Mat37 = Eigen::Matrix<double, 3, 7>;

// The 3 x 7 rows of the 1-ring fit for vertex v: A_v (s, h, t) = s v + h x v + t (thesis eq. 2-11).
Mat37 ring_row(const Points& V, int v) {
  const double x = V(v, 0), y = V(v, 1), z = V(v, 2);
  Mat37 a;
  a << x, 0, z, -y, 1, 0, 0,  //
      y, -z, 0, x, 0, 1, 0,   //
      z, y, -x, 0, 0, 0, 1;
  return a;
}

// N = sum_k A_k^T A_k over the 1-ring `ring` ({i} and its neighbours). Without the translation fit (thesis eq.
// 2-12) the translation unknowns are decoupled so that they drop out.
Mat7 fit_normal(const Points& V, const std::vector<int>& ring, bool translation) {
  Mat7 N = Mat7::Zero();
  for (int v : ring) {
    const Mat37 a = ring_row(V, v);
    N.noalias() += a.transpose() * a;
  }
  if (!translation) {
    N.block<3, 4>(4, 0).setZero();
    N.block<4, 3>(0, 4).setZero();
    N.block<3, 3>(4, 4).setIdentity();
  }
  return N;
}

// N^-1 Z by one 7x7 Cholesky; a flat or collinear 1-ring leaves the fit underdetermined: the minimum-norm
// solution then.
template <int C>
Eigen::Matrix<double, 7, C> solve_fit(const Mat7& N, const Eigen::Matrix<double, 7, C>& Z) {
  Eigen::LLT<Mat7> llt(N);
  const auto d = llt.matrixLLT().diagonal();
  if (llt.info() == Eigen::Success && d.minCoeff() > 1e-6 * d.maxCoeff()) return llt.solve(Z);  // pivots within 1e-12
  return Eigen::MatrixXd(N).completeOrthogonalDecomposition().solve(Eigen::MatrixXd(Z));
}
}  // namespace

const EnumText<EnergyKind>& enum_text(EnergyKind) {
  static const EnumText<EnergyKind> t{"energy", {{EnergyKind::Lap, "lap"}, {EnergyKind::Tf, "tf"}}};
  return t;
}

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
  // A_k the 3 x 7 matrix of v_k (ring_row). (s,h,t) = N^-1 sum_k A_k^T v'_k with N = sum_k A_k^T A_k, and
  // T_i delta_i = G (s,h) with G = [delta, -[delta]x]. So the block of column k is
  // M_k = G (N^-1)[0:4, :] A_k^T, computed without forming the stacked 3m x 7 matrix.
  const Mat7 N = fit_normal(V_, cols, opt_.tf_translation);
  const Vec3 dl = delta_.row(i).transpose();
  Eigen::Matrix<double, 3, 4> G;
  G << dl(0), 0, dl(2), -dl(1),  //
      dl(1), -dl(2), 0, dl(0),   //
      dl(2), dl(1), -dl(0), 0;   // G (s,h) = s*delta + h x delta, the same pattern as A_k's rows
  // W = G (N^-1)[0:4, :], i.e. W^T = N^-1 [G^T; 0] (N is symmetric): three solves instead of an inverse (this
  // fit is most of the TF build's arithmetic).
  Eigen::Matrix<double, 7, 3> Z = Eigen::Matrix<double, 7, 3>::Zero();
  Z.topRows<4>() = G.transpose();
  const Mat37 W = solve_fit(N, Z).transpose();
  // Expand the scalar Laplacian row into 3x3 blocks: C_k = L_ik I - M_k.
  const std::size_t b2 = 9;
  coeffs.resize(b2 * m + m);  // scratch: the m Laplacian scalars move to the tail
  std::copy_backward(coeffs.begin(), coeffs.begin() + m, coeffs.end());
  const double* lap = coeffs.data() + b2 * m;
  for (int t = 0; t < m; ++t) {
    const Mat37 a = ring_row(V_, cols[t]);
    const Mat3 M = W * a.transpose();
    double* blk = coeffs.data() + b2 * t;
    const double l = lap[t];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) blk[3 * r + c] = (r == c ? l : 0.0) - M(r, c);
  }
  coeffs.resize(b2 * m);
}

Mat3 EnergyOperator::fitted_rotation(int i, const Points& deformed) const {
  std::vector<int> ring(adj_.begin(i), adj_.end(i));
  ring.push_back(i);
  Eigen::Matrix<double, 7, 1> rhs = Eigen::Matrix<double, 7, 1>::Zero();
  for (int v : ring) rhs.noalias() += ring_row(V_, v).transpose() * deformed.row(v).transpose();
  if (!opt_.tf_translation) rhs.tail<3>().setZero();
  const Eigen::Matrix<double, 7, 1> sht = solve_fit(fit_normal(V_, ring, opt_.tf_translation), rhs);
  // s I + [h]x = r (cos phi I + sin phi [a]x) with a = h / |h|, r = |(s, h)|, phi = atan2(|h|, s): the rotation
  // by phi about a times the symmetric r (I - (1 - cos phi) a a^T), whose eigenvalues r, r, s are the scales.
  const Vec3 h = sht.segment<3>(1);
  if (h.norm() == 0) return Mat3::Identity();
  return Eigen::AngleAxisd(std::atan2(h.norm(), sht(0)), h.normalized()).toRotationMatrix();
}

}  // namespace db
