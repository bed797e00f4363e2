#pragma once
//! A handle drag: the frames of an interactive edit interpolate the identity to the final handle transform.
#include "core/types.h"

namespace db {

//! Fraction f in [0,1] of T: a rigid T is interpolated by axis-angle and linear translation; any other
//! linear part is blended linearly (a rotation cannot be extracted meaningfully).
Mat4 interpolate_transform(const Mat4& T, double f);

}  // namespace db
