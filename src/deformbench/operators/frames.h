#pragma once
//! Local frames and discrete forms of linear rotation-invariant coordinates (Lipman et al. 2005; thesis 3.1-3.2,
//! 4.3): area-weighted vertex normals, per-vertex orthonormal frames (b1, b2, N) built by one of several
//! strategies for the tangent axis b1, the 1-ring edge vectors expressed in those frames, the frame-to-frame
//! connection coefficients, a per-vertex curvature tensor, and the orthonormalization of solved frames.
//!
//! Conventions: a frame is a 3x3 matrix F = [b1 b2 N] (columns), right-handed (b2 = N x b1, so b1 x b2 = N;
//! the thesis writes b2 = b1 x N and calls it right-handed, which contradicts itself: we keep right-handed).
//! Per-edge arrays are aligned with Adjacency::nbr: entry off[i]+t belongs to the directed edge (i, t-th
//! neighbour of i).
#include <string>
#include <vector>

#include "core/enum_text.h"
#include "solvers/base/types.h"
#include "mesh/mesh.h"

namespace db {

//! How b1 (the tangent X axis) of each frame is chosen.
enum class FrameStrategy {
  First,        //!< projection of the edge to the neighbour with the lowest index (Lipman: "any neighbour")
  Random,       //!< projection of the edge to a neighbour drawn by a seeded std::mt19937 (reproducible)
  HeightAngle,  //!< the neighbour of largest height angle theta = acos(<e, N>/|e|) - pi/2 (thesis eq. 4-4)
  Curvature     //!< the maximum principal direction of a 1-ring averaged curvature tensor (beyond the thesis)
};
//! "first" | "random" | "height_angle" | "curvature" (core/enum_text.h).
const EnumText<FrameStrategy>& enum_text(FrameStrategy);

//! How a solved (non-orthonormal) frame is turned back into a rotation.
enum class Orthonormalization {
  GramSchmidt,  //!< b1 normalized first, then b2 against b1, then N against both (order matters)
  Polar         //!< the orthogonal polar factor U V^T of F = U S V^T, made proper (nearest rotation)
};
//! "gram_schmidt" | "polar" (core/enum_text.h).
const EnumText<Orthonormalization>& enum_text(Orthonormalization);

//! Unit area-weighted vertex normals (thesis eq. 3-14: sum of face unit normals weighted by face area, i.e. the
//! sum of face cross products, normalized). #V by 3. \throw InputError for a vertex whose normal vanishes.
Points vertex_normals(const Points& V, const Faces& F);

//! Per-vertex curvature estimate: normal curvatures along the 1-ring edges, kappa_j = -2 <e_j, N> / |e_j|^2
//! (positive where the surface bends away from the outward normal, e.g. a convex surface), fitted in least
//! squares by a symmetric tangent tensor II with kappa(d) = d^T II d for unit tangent d; the tensors are then
//! averaged over the 1-ring (each projected into the tangent plane of the centre) to suppress sampling noise.
struct CurvatureTensor {
  Mat3 II = Mat3::Zero();    //!< averaged tensor, 3x3 symmetric, acting on the tangent plane (II N = 0)
  double k_max = 0, k_min = 0;  //!< principal curvatures (eigenvalues in the tangent plane), k_max >= k_min
  Vec3 dir_max = Vec3::Zero();  //!< unit maximum principal direction (tangent), sign arbitrary
  bool defined = false;  //!< false: fewer than 3 neighbours, or (nearly) umbilic / flat: direction arbitrary
};
//! \param N unit normals (vertex_normals). One entry per vertex.
std::vector<CurvatureTensor> curvature_tensors(const Points& V, const Adjacency& adj, const Points& N);

//! Frames of every vertex.
struct FrameField {
  std::vector<Mat3> F;      //!< per vertex [b1 b2 N], orthonormal, right-handed
  std::vector<int> ref;     //!< per vertex: neighbour whose projected edge is b1, or -1 (curvature direction)
  int fallbacks = 0;        //!< vertices where the strategy had no usable direction and the first usable
                            //!< neighbour was taken (curvature: undefined tensor; any: edge parallel to N)
};

//! Builds frames with the given strategy; N from vertex_normals. `seed` is used by Random only.
//! \throw InputError when some vertex has no neighbour edge with a tangent component.
FrameField compute_frames(const Points& V, const Adjacency& adj, const Points& N, FrameStrategy strategy,
                          unsigned seed = 1);

//! Discrete forms (thesis eqs. 3-12, 3-13): d_ij = F_i^T (x_j - x_i) = (<e, b1_i>, <e, b2_i>, L_ij = <e, N_i>)
//! for every directed edge, aligned with adj.nbr. Together they determine the first form (tangent lengths and
//! angles) and the second form (heights L) of each 1-ring.
std::vector<Vec3> discrete_forms(const Points& V, const Adjacency& adj, const std::vector<Mat3>& frames);

//! Frame connection (thesis eqs. 3-16, 3-17): R_ij = F_i^T F_j, the coordinates of frame j in frame i, so that
//! F_j = F_i R_ij (column k of R_ij holds the Gamma / A coefficients of the k-th vector of frame j).
inline Mat3 frame_connection(const Mat3& Fi, const Mat3& Fj) { return Fi.transpose() * Fj; }

//! Orthonormalizes one solved frame [b1 b2 N].
//! \throw SolverError when the frame is (numerically) rank deficient, naming `vertex`.
Mat3 orthonormalize(const Mat3& F, Orthonormalization o, int vertex = -1);

//! Nearest proper rotation to a 3x3 matrix (polar factor with det +1). \throw InputError when M is singular or
//! not finite.
Mat3 nearest_rotation(const Mat3& M);

}  // namespace db
