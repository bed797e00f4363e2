#pragma once
//! How fast this machine is at the moment: the rates the budget predictions divide flop counts by, and the rates
//! drivers measure just before and after each cell (on a shared machine they move by 2x within a day, so a slow
//! window shows in them rather than as a regression of the code).

#include <cstddef>

namespace db::harness {

//! Machine rates in flop/s, measured once per driver run (a few tenths of a second).
struct MachineRates {
  double dense = 1e9;   //!< Eigen dense GEMM, one thread: the dense build's SYRK and LLT run on this kernel
  double sparse = 1e8;  //!< Eigen sparse A^T A product: what the sparse builds run at (indexing-bound)
  double stream = 1e9;  //!< dense matrix-vector product out of cache: what triangular solves run at (memory-bound)
  static MachineRates measure();
  //! The system BLAS's dgemm on m x m matrices with its own threads (best of three; m = 1024: ~0.2 s): the ceiling
  //! of the sparse factorizations' dense kernels at the moment it runs.
  static double blas_gemm(int m = 1024);
  //! Bytes per second read from memory by worker_threads() threads summing an array of `bytes` (default 128 MB;
  //! best of three): the rate the triangular solves stream the factor at, at best.
  static double read_bandwidth(std::size_t bytes = std::size_t(128) << 20);
  //! Bytes per second at which worker_threads() threads write memory this process has not touched before: a
  //! fresh anonymous mapping of `bytes` (default 256 MB), advised for huge pages as the factor's storage is, one
  //! write per 4 KB page, timed once (a second mapping would reuse the pages the first gave back). Why: every
  //! factorization writes its whole factor into such memory, and on a virtual machine whose host backs guest
  //! memory only on first use (free page reporting) that costs more than the arithmetic of a large factor; this
  //! rate beside an init time tells whether the machine or the code moved.
  static double first_touch(std::size_t bytes = std::size_t(256) << 20);
};

}  // namespace db::harness
