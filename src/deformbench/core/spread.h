#pragma once
//! A timing's repeats summarized: its median with the least and largest repeat (frames of a drag, repetitions of a
//! phase). Used by the drag loop (methods/drag.h), the command line's report and every result table.
#include <string>
#include <vector>

namespace db {

//! Median (mean of the two middle values for an even count). NaN for an empty input.
double median(std::vector<double> v);

//! The median with the least and the largest value and how many there were (NaN and 0 for none).
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

//! The spread of a timed measure over its repeats (frames of a drag, repetitions of a phase, fresh children of a
//! cell): "NAME_s" is the median, "NAME_min_s" and "NAME_max_s" the least and largest repeat, "NAME_reps" how many
//! repeats there were (count). Every CSV uses these names (the deformation's record, methods/deform_record.h,
//! too). `stat`: "min", "max" or "reps".
//! \throw Error for a name that does not end in "_s" or another stat.
std::string spread_name(const std::string& timed, const std::string& stat);

}  // namespace db
