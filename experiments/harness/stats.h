#pragma once
//! Small statistics for result tables: medians over frames, power-law fits of cost against size.
#include <string>
#include <vector>

namespace db::harness {

//! Median (mean of the two middle values for an even count). NaN for an empty input.
double median(std::vector<double> v);

//! A timing's repeats summarized: the median with the least and the largest value and how many there were (NaN
//! and 0 for none).
struct Spread {
  double min, median, max;
  int count = 0;
};
//! The spread of repeats in the order they ran (NaN samples are none): the median of them all; the least, the
//! largest and the count leave the first out from three repeats on. The first warms up, slower by design (a drag's
//! first frame also stores the rest pose's forward substitution and touches fresh memory; a first factorization or
//! solve allocates): counted in, it would set every cell's largest repeat and flag it. (From three on the median of
//! all lies within the range of the others.)
Spread spread(std::vector<double> v);
//! Repeats further apart than this (max > ratio x min) are flagged wherever a timing is shown (reports, the CLI): a
//! thread waited on a descheduled worker or the machine was busy, and the median may be unreliable.
constexpr double kSpreadFlagRatio = 2.0;
inline bool spread_flagged(const Spread& s) { return s.count > 1 && s.max > kSpreadFlagRatio * s.min; }
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
