#pragma once
//! Where a measurement came from: attached to every result row (git sha, BLAS library and core, threads, CPU).
#include <string>
#include <utility>
#include <vector>

namespace db {

struct Provenance {
  std::string git_sha;      //!< short sha of the sources this binary was compiled from, "+dirty" when they had
                            //!< uncommitted changes (DEFORMBENCH_GIT_SHA overrides it)
  std::string blas;         //!< BLAS library as loaded (e.g. "openblas 0.3.21")
  std::string blas_core;    //!< OpenBLAS kernel set in use (openblas_get_corename), "n/a" otherwise
  std::string blas_coretype_env;  //!< OPENBLAS_CORETYPE as set by the user, "" when unset (auto-detected)
  int blas_threads = 1;     //!< threads the BLAS will use
  int build_threads = 1;    //!< threads of the structured assembly (DEFORMBENCH_THREADS)
  int hardware_threads = 1;
  std::string cpu;          //!< /proc/cpuinfo model name
  std::string compiler;
  std::string timestamp;    //!< UTC, ISO 8601

  //! Column name / value pairs, in a fixed order, for CSV rows.
  std::vector<std::pair<std::string, std::string>> columns() const;
};

//! Reads everything once per process (cached).
const Provenance& provenance();

//! One line for logs: "git abc123 | openblas 0.3.21 core Prescott (auto) | 2 threads".
std::string provenance_summary();

}  // namespace db
