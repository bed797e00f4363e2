#pragma once
#include <chrono>
#include <ctime>

namespace db {

//! Wall-clock stopwatch (steady clock), seconds as double.
class Timer {
 public:
  Timer() : start_(Clock::now()) {}
  void reset() { start_ = Clock::now(); }
  double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

 private:
  using Clock = std::chrono::steady_clock;
  Clock::time_point start_;
};

//! Seconds of CPU time this process has used, all its threads (CLOCK_PROCESS_CPUTIME_ID).
inline double process_cpu_seconds() {
  timespec t{};
  ::clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

//! Like Timer, in CPU seconds of this process: what a phase cost in work, which time-slicing by other processes
//! on a shared machine does not lengthen (wall time does).
class CpuTimer {
 public:
  CpuTimer() : start_(process_cpu_seconds()) {}
  double seconds() const { return process_cpu_seconds() - start_; }

 private:
  double start_;
};

}  // namespace db
