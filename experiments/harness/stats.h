#pragma once
//! Small statistics for result tables: medians over frames, power-law fits of cost against size.
#include <string>
#include <vector>

#include "core/spread.h"

namespace db::harness {

// Medians and spreads of repeats live in the library (core/spread.h: the drag loop reports them too).
using db::kSpreadFlagRatio;
using db::median;
using db::Spread;
using db::spread;
using db::spread_flagged;

//! The fewest points a power law is fitted to: through two or three points a line fits (nearly) exactly, and its
//! r^2 of about 1 says nothing about the law.
inline constexpr int kMinFitPoints = 4;

//! y = c * x^exponent fitted by least squares on (log x, log y). Points with x <= 0 or y <= 0 are skipped.
struct PowerFit {
  double exponent = 0, coefficient = 0;
  double r2 = 0;  //!< coefficient of determination in log space
  int points = 0;  //!< points used; a fit needs >= kMinFitPoints of them, >= 2 distinct x (exponent NaN otherwise)
};
PowerFit fit_power_law(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace db::harness
