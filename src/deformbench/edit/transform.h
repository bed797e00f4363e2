#pragma once
//! Handle transforms: constructors and a one-line textual spec used by .edit files and command lines.
#include <string>
#include <vector>

#include "solvers/base/types.h"

namespace db {

//! Affine translation by t.
Mat4 translation(const Vec3& t);

//! Rotation by `degrees` (right-hand rule) about the line through `point` with direction `axis` (normalized here).
//! \throw InputError for a zero or non-finite axis.
Mat4 rotation_about_axis(const Vec3& axis, double degrees, const Vec3& point = Vec3::Zero());

//! Parses a transform spec:
//!   translate:x,y,z
//!   rotate:DEG:ax,ay,az[:px,py,pz]      (rotation_about_axis; the point defaults to the origin)
//!   matrix:m00,m01,...,m33              (16 values, row major; must be affine)
//!   def:path                            (a Botsch-Sorkine .def file, see read_def)
//! \throw InputError naming the spec on anything else.
Mat4 parse_transform(const std::string& spec);

//! As parse_transform, with a relative `def:` path resolved against base_dir (the directory of an .edit file).
Mat4 parse_transform(const std::string& spec, const std::string& base_dir);

//! Parses a comma-separated list of exactly `count` finite numbers ("1,2.5,-3"); `what` names it in errors.
//! \throw InputError on a wrong count or a bad number.
std::vector<double> parse_numbers(const std::string& text, std::size_t count, const std::string& what);

}  // namespace db
