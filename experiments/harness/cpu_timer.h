#pragma once
//! CPU-time stopwatch of this process (core/timer.h). The tracking suite gates on it (experiments/track.cpp,
//! python/dbtools/track/gate.py); cells run single-threaded there, so it is the phase's own work.
#include "core/timer.h"

namespace db::harness {

using db::CpuTimer;
using db::process_cpu_seconds;

}  // namespace db::harness
