#include "applications/zipper.h"

#include <cmath>

#include "core/error.h"

namespace db {
namespace {

// The angle of loop position k, 2 pi for k = m (the first vertex again, once around).
double angle_at(const ZipperLoop& l, std::size_t k) { return k < l.ids.size() ? l.angle[k] : 2 * M_PI; }

void check_loop(const ZipperLoop& l, const char* what) {
  if (l.ids.empty() || l.ids.size() != l.angle.size())
    throw InputError(std::string("zipper: the ") + what + " loop is empty or its ids and angles disagree");
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
    // Advance the loop whose next vertex comes first in angle (the outer one on a tie, or when the inner is done).
    if (j == mi || (i < mo && angle_at(outer, i + 1) <= angle_at(inner, j + 1))) {
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
