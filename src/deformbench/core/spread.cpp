#include "core/spread.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "solvers/base/error.h"

namespace db {

double median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

Spread spread(std::vector<double> v) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return std::isnan(x); }), v.end());
  if (v.empty()) return {median(v), median(v), median(v), 0};
  const auto first = v.begin() + (v.size() >= 3 ? 1 : 0);  // past the warm-up repeat
  const auto [lo, hi] = std::minmax_element(first, v.end());
  return {*lo, median(v), *hi, static_cast<int>(v.end() - first)};
}

std::string spread_name(const std::string& timed, const std::string& stat) {
  if (timed.size() < 3 || timed.compare(timed.size() - 2, 2, "_s") != 0)
    throw Error("spread_name: '" + timed + "' is not a timed measure");
  const std::string base = timed.substr(0, timed.size() - 2);
  if (stat == "min" || stat == "max") return base + "_" + stat + "_s";
  if (stat == "reps") return base + "_reps";
  throw Error("spread_name: unknown statistic '" + stat + "'");
}

}  // namespace db
