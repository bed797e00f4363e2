#pragma once
//! CPU-time stopwatch of this process (all its threads): what a phase cost in work, which time-slicing by other
//! processes on a shared machine does not lengthen (wall time does). The tracking suite gates on it
//! (experiments/track.cpp, python/dbtools/track/gate.py); cells run single-threaded there, so it is the phase's own work.
#include <ctime>

namespace db::harness {

//! Seconds of CPU time this process has used (CLOCK_PROCESS_CPUTIME_ID).
inline double process_cpu_seconds() {
  timespec t{};
  ::clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

//! Like db::Timer, in CPU seconds of this process.
class CpuTimer {
 public:
  CpuTimer() : start_(process_cpu_seconds()) {}
  double seconds() const { return process_cpu_seconds() - start_; }

 private:
  double start_;
};

}  // namespace db::harness
