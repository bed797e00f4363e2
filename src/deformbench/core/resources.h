#pragma once
//! Process resource readings (Linux /proc).
#include <cstddef>

namespace db {

//! Peak resident set size of this process so far, bytes (VmHWM).
std::size_t peak_rss_bytes();
//! Current resident set size, bytes (VmRSS).
std::size_t current_rss_bytes();
//! Physical memory of the machine, bytes.
std::size_t physical_memory_bytes();

//! Threads for the project's own parallel loops (structured assembly): DEFORMBENCH_THREADS when set,
//! else the hardware threads.
int worker_threads();

}  // namespace db
