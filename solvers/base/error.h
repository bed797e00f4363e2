#pragma once
//! Typed failures. Every tool maps them to a message and a distinct non-zero exit code (see exit_code()).
#include <stdexcept>
#include <string>

namespace db {

struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};
//! A command line that cannot run: options that do not go together, an option the chosen method does not use, an
//! output path that cannot be written (exit code 1, like a parse error).
struct UsageError : Error {
  using Error::Error;
};
//! Unreadable / malformed / degenerate mesh, inconsistent selection or transform.
struct InputError : Error {
  using Error::Error;
};
//! A factorization or solve that failed: singular, indefinite, not converged, non-finite result.
struct SolverError : Error {
  using Error::Error;
};
//! A cell predicted to exceed its memory or time budget; never attempted.
struct BudgetError : Error {
  using Error::Error;
};

//! Exit codes used by every executable: 2 input, 3 solver, 4 budget, 1 usage and anything else (core/cli.h).
inline int exit_code(const std::exception& e) {
  if (dynamic_cast<const InputError*>(&e)) return 2;
  if (dynamic_cast<const SolverError*>(&e)) return 3;
  if (dynamic_cast<const BudgetError*>(&e)) return 4;
  return 1;
}

}  // namespace db
