#pragma once
//! Coordinates are centered and scaled (bounding-box center to the origin, diagonal to 1) before systems are
//! built and restored afterwards. Why: the transform fit of TF mixes positions with a constant column; in raw
//! coordinates far from the origin its 7x7 normal matrices are so ill-conditioned that round-off makes the
//! global system indefinite (the BS08 cactus case). It also makes every geometric test that follows (TF's
//! collinearity check, degenerate frames) independent of the model's scale: a mesh scaled by 1e200 or 1e-300
//! deforms like the unscaled one.
#include "solvers/base/types.h"

namespace db {

struct Normalization {
  Vec3 center = Vec3::Zero();
  double scale = 1.0;  //!< normalized = (p - center) * scale

  //! \throw InputError naming the coordinates when the bounding-box diagonal cannot serve as the unit
  //! (checked_bbox_diagonal: beyond the largest double, or below the smallest normal one).
  static Normalization fit(const Points& V);
  static Normalization identity() { return {}; }
  Points apply(const Points& V) const;
  //! \throw InputError naming the first vertex whose restored coordinate overflows (a result beyond the largest
  //! double, e.g. a handle moved far off a model already near it).
  Points restore(const Points& Vn) const;
  //! The same affine map expressed in normalized coordinates: S T S^-1.
  Mat4 conjugate(const Mat4& T) const;
};

}  // namespace db
