#include "applications/tangent_frames.h"

#include "operators/frames.h"

namespace db {
namespace {

// Any unit vector perpendicular to n: for a 1-ring whose parameter Jacobian is degenerate (never for a Tutte
// map's interior, which is bijective; kept for safety at boundary corners).
Vec3 any_perpendicular(const Vec3& n) {
  const Vec3 a = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  return (a - n * n.dot(a)).normalized();
}

}  // namespace

std::vector<Mat3> tangent_frames(const Mesh& mesh, const Adjacency& adj, const UV& uv) {
  const Points N = vertex_normals(mesh.V, mesh.F);
  std::vector<Mat3> frames(static_cast<std::size_t>(mesh.num_vertices()));
  for (int i = 0; i < mesh.num_vertices(); ++i) {
    // J = (sum dp duv^T) (sum duv duv^T)^-1; only its first column is needed.
    Eigen::Matrix<double, 3, 2> PU = Eigen::Matrix<double, 3, 2>::Zero();
    Eigen::Matrix2d UU = Eigen::Matrix2d::Zero();
    for (const int* q = adj.begin(i); q != adj.end(i); ++q) {
      const Vec3 dp = (mesh.V.row(*q) - mesh.V.row(i)).transpose();
      const Eigen::Vector2d du = (uv.row(*q) - uv.row(i)).transpose();
      PU += dp * du.transpose();
      UU += du * du.transpose();
    }
    const Vec3 n = N.row(i).transpose();
    Vec3 t = Vec3::Zero();
    if (std::abs(UU.determinant()) > 1e-300) t = PU * UU.inverse().col(0);
    t -= n * n.dot(t);
    t = t.norm() > 1e-12 * std::max(1.0, PU.norm()) ? t.normalized() : any_perpendicular(n);
    frames[static_cast<std::size_t>(i)].col(0) = t;
    frames[static_cast<std::size_t>(i)].col(1) = n.cross(t);
    frames[static_cast<std::size_t>(i)].col(2) = n;
  }
  return frames;
}

}  // namespace db
