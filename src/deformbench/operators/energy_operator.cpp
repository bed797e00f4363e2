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
  const int d = adj_.degree(i);
  const int m = d + 1;
  cols.clear();
  // Position of i among its sorted neighbours keeps cols ascending.
  std::vector<double> lap(m);
  {
    bool placed = false;
    for (int s = adj_.off[i]; s < adj_.off[i + 1]; ++s) {
      const int j = adj_.nbr[s];
      if (!placed && i < j) {
        cols.push_back(i);
        lap[cols.size() - 1] = 1.0;
        placed = true;
      }
      cols.push_back(j);
      lap[cols.size() - 1] = -w_[s];
    }
    if (!placed) {
      cols.push_back(i);
      lap[cols.size() - 1] = 1.0;
    }
  }
  if (kind_ == EnergyKind::Lap) {
    coeffs.assign(lap.begin(), lap.end());
    return;
  }

  // TF: fit T_i = (s, h, t) to the 1-ring: minimize sum_k ||T_i v_k - v'_k||^2 (thesis eq. 2-11).
  // (s,h[,t]) = P b with P = (A^T A)^{-1} A^T, b the stacked v'_k; then T_i delta_i = [delta, -[delta]x] (s,h).
  const int p = opt_.tf_translation ? 7 : 4;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(3 * m, p);
  for (int t = 0; t < m; ++t) {
    const double x = V_(cols[t], 0), y = V_(cols[t], 1), z = V_(cols[t], 2);
    A.row(3 * t + 0).head<4>() << x, 0, z, -y;
    A.row(3 * t + 1).head<4>() << y, -z, 0, x;
    A.row(3 * t + 2).head<4>() << z, y, -x, 0;
    if (p == 7) {
      A(3 * t + 0, 4) = 1;
      A(3 * t + 1, 5) = 1;
      A(3 * t + 2, 6) = 1;
    }
  }
  const Eigen::MatrixXd AtA = A.transpose() * A;
  Eigen::LDLT<Eigen::MatrixXd> ldlt(AtA);
  Eigen::MatrixXd P;
  if (ldlt.info() == Eigen::Success && ldlt.isPositive() &&
      ldlt.vectorD().minCoeff() > 1e-12 * ldlt.vectorD().maxCoeff()) {
    P = ldlt.solve(A.transpose());
  } else {
    // A flat or collinear 1-ring leaves the fit underdetermined: take the minimum-norm transform.
    P = A.completeOrthogonalDecomposition().pseudoInverse();
  }
  const Vec3 dl = delta_.row(i).transpose();
  Eigen::Matrix<double, 3, 4> G;
  G << dl(0), 0, dl(2), -dl(1),  //
      dl(1), -dl(2), 0, dl(0),   //
      dl(2), dl(1), -dl(0), 0;   // G (s,h) = s*delta + h x delta, same pattern as A's rows
  const Eigen::MatrixXd Q = G * P.topRows<4>();  // 3 x 3m
  coeffs.assign(static_cast<std::size_t>(9 * m), 0.0);
  for (int t = 0; t < m; ++t) {
    double* blk = coeffs.data() + 9 * t;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) blk[3 * r + c] = (r == c ? lap[t] : 0.0) - Q(r, 3 * t + c);
  }
}

}  // namespace db
