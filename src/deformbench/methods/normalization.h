#pragma once
//! Coordinates are centered and scaled (bounding-box center to the origin, diagonal to 1) before systems are
//! built and restored afterwards. Why: the transform fit of TF mixes positions with a constant column; in raw
//! coordinates far from the origin its 7x7 normal matrices are so ill-conditioned that round-off makes the
//! global system indefinite (the BS08 cactus case).
#include "core/types.h"

namespace db {

struct Normalization {
  Vec3 center = Vec3::Zero();
  double scale = 1.0;  //!< normalized = (p - center) * scale

  static Normalization fit(const Points& V);
  static Normalization identity() { return {}; }
  Points apply(const Points& V) const;
  Points restore(const Points& Vn) const;
  //! The same affine map expressed in normalized coordinates: S T S^-1.
  Mat4 conjugate(const Mat4& T) const;
};

}  // namespace db
