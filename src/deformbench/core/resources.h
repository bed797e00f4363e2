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

}  // namespace db
