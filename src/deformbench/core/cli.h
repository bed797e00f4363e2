#pragma once
//! Command lines of every executable (deformbench, meshtool, the experiment drivers) on CLI11: one exit-code
//! policy, numbers checked as numbers, misspelled options named with the nearest valid one, and output paths
//! checked before any work.
//!
//! Exit codes (docs/cli.md): 0 ok, 1 usage (unknown or misspelled option, a value out of range, options that do not
//! go together), 2 bad input (a file or an edit), 3 solver failure, 4 over a memory or time budget.
#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace db::cli {

//! A whole number in [min, max], plain or in scientific notation ("1e3", "2.5e2"): rejects "2.5", "1e-1", "nan",
//! "0x10" and out-of-range values, each with its own message ("--frames: 2.5 is not a whole number"). Add it with
//! ->transform() so the option converts the number it names ("1e3" -> 1000); ->check() validates only.
CLI::Validator Integer(long long min, long long max);
//! A finite decimal number in [min, max] (rejects nan and inf).
CLI::Validator Real(double min, double max);
//! One of `values` (the message lists them).
CLI::Validator OneOf(const std::vector<std::string>& values);

//! Parses argv into `app`, then runs `body`; returns the process exit code. --help prints the help generated
//! from `app`'s definitions and returns 0. A parse error prints "<tool>: error: ..." (an unknown option with
//! the nearest valid one) and returns 1; exceptions from `body` map through db::exit_code (InputError 2,
//! SolverError 3, BudgetError 4, UsageError and anything else 1).
int run(CLI::App& app, int argc, char** argv, const std::function<int()>& body);

//! Checks a directory the run will write into (an out-of-core scratch directory, say) before any work: it exists
//! as a directory, is writable and its file system is not full. \throw UsageError naming `option` and the cause.
void check_directory(const std::string& option, const std::string& dir);

//! Checks an output path before any input is read: its directory exists and is writable, its extension is one
//! of `extensions` (lower case with the dot, e.g. ".ply"; empty = any) and it is not one of `inputs` (the same
//! file, however spelled). \throw UsageError naming `option`.
void check_output(const std::string& option, const std::string& path, const std::vector<std::string>& extensions,
                  const std::vector<std::string>& inputs = {});

}  // namespace db::cli
