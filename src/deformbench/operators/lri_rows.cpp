#include "operators/lri_rows.h"

#include "operators/frames.h"

namespace db {

EdgeRows lri_frame_rows(const std::vector<Mat3>& F) {
  return {3, [&F](int i, int j, int, double* P, double* Q) {
            const Mat3 R = frame_connection(F[i], F[j]);
            for (int r = 0; r < 3; ++r)
              for (int c = 0; c < 3; ++c) {
                P[r * 3 + c] = -R(c, r);
                Q[r * 3 + c] = r == c ? 1.0 : 0.0;
              }
          }};
}

EdgeRows lri_position_rows() {
  return {1, [](int, int, int, double* P, double* Q) {
            P[0] = -1.0;
            Q[0] = 1.0;
          }};
}

void lri_position_targets(const Adjacency& adj, const std::vector<Mat3>& frames, const std::vector<Vec3>& forms,
                          DenseMat& t) {
  t.resize(static_cast<Eigen::Index>(adj.nbr.size()), 3);
  for (int i = 0; i < adj.num_vertices(); ++i)
    for (int s = adj.off[i]; s < adj.off[i + 1]; ++s) t.row(s) = (frames[i] * forms[s]).transpose();
}

}  // namespace db
