#pragma once
//! Running a measurement in a fresh child process (fork + exec), so that cells never share a heap, a page
//! cache of freed blocks or a high-water mark.
#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "core/child_process.h"

namespace db::harness {

// The child runner lives in the library (core/child_process.h): `deformbench advise` runs its backends with it too.
using db::ChildRun;
using db::limit_address_space;
using db::run_child;
using db::self_executable;

//! Percent-encoding for the "KEY=VALUE ..." result line a cell child prints: spaces, '=', '%', control and
//! non-ASCII bytes become %XX, so a value is one token.
std::string pct_encode(const std::string& s);
std::string pct_decode(const std::string& s);
//! The fields (decoded values) of the last line of `out` that starts with "TAG ", e.g. "DBCELL status=ok n=1197".
//! \throw Error when there is no such line or a field has no '='.
std::vector<std::pair<std::string, std::string>> parse_result_line(const std::string& out, const std::string& tag);

//! How a cell's measurement ended, on the child's side.
struct CellOutcome {
  std::string status = "ok";  //!< ok | #over (BudgetError) | error
  std::string message;
  int exit_code = 0;  //!< the process exit code (solvers/base/error.h's codes)
};

//! Runs a cell's measurement in the child and turns what `measure` throws into the outcome. Never throws.
CellOutcome run_guarded_cell(const std::function<void()>& measure);

}  // namespace db::harness
