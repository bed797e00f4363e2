#include "applications/zipper.h"

#include <cmath>

#include "solvers/base/error.h"

namespace db {
namespace {

// The angle of loop position k, 2 pi for k = m (the first vertex again, once around).
double angle_at(const ZipperLoop& l, std::size_t k) { return k < l.ids.size() ? l.angle[k] : 2 * M_PI; }

void check_loop(const ZipperLoop& l, const char* what) {
  const auto n = static_cast<Eigen::Index>(l.ids.size());
  if (l.ids.empty() || l.ids.size() != l.angle.size() || (l.at.rows() != 0 && l.at.rows() != n) ||
      (l.normal.rows() != 0 && l.normal.rows() != n))
    throw InputError(std::string("zipper: the ") + what + " loop is empty or its ids and angles disagree");
}

// Whether triangle (a, b, c), given as loop positions, faces along the outer loop's normal at its vertex a.
double facing(const ZipperLoop& outer, std::size_t i, const Vec3& b, const Vec3& c) {
  const Vec3 a = outer.at.row(i);
  return (b - a).cross(c - a).dot(outer.normal.row(i));
}

// Whether to close the outer edge (i, i+1) before the inner edge (j, j+1): by angle, or with positions by the
// shorter new diagonal (the greedy of Fuchs et al. 1977; it follows the loops' geometry where the angles of a
// staircase loop do not), unless that triangle folds (faces against the normal) and the other does not.
bool advance_outer(const ZipperLoop& outer, const ZipperLoop& inner, std::size_t i, std::size_t j) {
  const std::size_t mo = outer.ids.size(), mi = inner.ids.size();
  if (j == mi) return true;
  if (i == mo) return false;
  const bool by_angle = angle_at(outer, i + 1) <= angle_at(inner, j + 1);
  if (outer.normal.rows() == 0 || inner.at.rows() == 0) return by_angle;
  const Vec3 o0 = outer.at.row(i % mo), o1 = outer.at.row((i + 1) % mo);
  const Vec3 s0 = inner.at.row(j % mi), s1 = inner.at.row((j + 1) % mi);
  const bool shorter = (o1 - s0).squaredNorm() <= (o0 - s1).squaredNorm();
  const bool outer_ok = facing(outer, i % mo, o1, s0) > 0, inner_ok = facing(outer, i % mo, s1, s0) > 0;
  return outer_ok == inner_ok ? shorter : outer_ok;
}

}  // namespace

Faces zipper_band(const ZipperLoop& outer, const ZipperLoop& inner) {
  check_loop(outer, "outer");
  check_loop(inner, "inner");
  const std::size_t mo = outer.ids.size(), mi = inner.ids.size();
  Faces F(static_cast<Eigen::Index>(mo + mi), 3);
  std::size_t i = 0, j = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const int a = outer.ids[i % mo], b = inner.ids[j % mi];
    if (advance_outer(outer, inner, i, j)) {
      F.row(f) << a, outer.ids[(i + 1) % mo], b;
      ++i;
    } else {
      F.row(f) << a, inner.ids[(j + 1) % mi], b;
      ++j;
    }
  }
  return F;
}

}  // namespace db
