// The machine's rates at this process's thread settings, for records made away from the drivers that measure them
// around each cell (Table 2-1, tracking): the system BLAS's dgemm on m x m matrices with its own threads
// (OPENBLAS_NUM_THREADS), the ceiling of the factorizations' dense kernels, and the rate DEFORMBENCH_THREADS worker
// threads read memory at, the ceiling of the triangular solves (both best of three), and the rate they first write
// fresh memory at, what every factorization pays to fill its factor's pages (harness/machine_rates.h).
// One row per run; a thread-scaling record runs it once per thread count, beside its deformations:
//
//   DEFORMBENCH_THREADS=16 OPENBLAS_NUM_THREADS=16 build/exp_machine_rates --csv rates.csv
#include <iostream>
#include <string>

#include <fmt/format.h>

#include "core/cli.h"
#include "core/csv.h"
#include "core/provenance.h"
#include "harness/machine_rates.h"
#include "solvers/base/resources.h"

namespace {

struct Options {
  int gemm_size = 2048;
  int first_touch_mb = 256;
  std::string csv;
};

int run(const Options& o) {
  if (!o.csv.empty()) db::cli::check_output("--csv", o.csv, {".csv"}, {});
  const double gemm = db::harness::MachineRates::blas_gemm(o.gemm_size);
  const double read = db::harness::MachineRates::read_bandwidth();
  const double touch = db::harness::MachineRates::first_touch(std::size_t(o.first_touch_mb) << 20);
  std::cout << fmt::format("threads {}: dgemm {:.1f} GFlop/s (m = {}), memory read {:.1f} GB/s, first touch of fresh "
                           "memory {:.2f} GB/s | {}\n",
                           db::worker_threads(), gemm / 1e9, o.gemm_size, read / 1e9, touch / 1e9,
                           db::provenance_summary());
  if (o.csv.empty()) return 0;
  db::CsvTable table;
  table.add({{"threads", std::to_string(db::worker_threads())},
             {"gemm_size", std::to_string(o.gemm_size)},
             {"blas_dgemm_flops", db::num(gemm)},
             {"memory_read_bytes_per_s", db::num(read)},
             {"first_touch_mb", std::to_string(o.first_touch_mb)},
             {"first_touch_bytes_per_s", db::num(touch)}});
  table.write(o.csv);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("The system BLAS's dgemm rate, the worker threads' memory read rate (best of three each) and the rate "
               "they first write fresh memory at, at this process's thread settings.",
               "exp_machine_rates");
  Options o;
  app.add_option("--gemm-size", o.gemm_size, "m of the m x m dgemm")->check(db::cli::Integer(64, 8192))
      ->capture_default_str();
  app.add_option("--first-touch-mb", o.first_touch_mb, "MB of fresh memory written for the first-touch rate")
      ->check(db::cli::Integer(1, 16384))->capture_default_str();
  app.add_option("--csv", o.csv, "write the row, with provenance, here");
  return db::cli::run(app, argc, argv, [&] { return run(o); });
}
