#pragma once
//! The deform options' table (methods/deform_options.h) as command-line options of any CLI11 app: `deformbench
//! deform` takes every row, `deformbench export-system` and `exp_solvers --edit` the rows of the groups that shape
//! the system (method, constraints, weights, LRI's frames). One place turns the table into flags and the parsed
//! flags into one DeformOptions.
#include <map>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "methods/deform_options.h"

namespace db {

//! The text of each option given, by key; filled by CLI11 while parsing.
using DeformOptionValues = std::map<std::string, std::string>;

//! The help groups of the options that shape a system (no backend, build or frame options).
const std::vector<std::string>& system_option_groups();

//! One option per row of the table whose group is in `groups` (empty: every row) and whose key is not in `skip`,
//! its text stored in `values` (which must outlive the app).
void add_deform_option_flags(CLI::App& app, DeformOptionValues& values, const std::vector<std::string>& groups = {},
                             const std::vector<std::string>& skip = {});

//! The keys of the table's options given on `app` (those add_deform_option_flags added to it), in table order.
std::vector<std::string> deform_option_keys_given(const CLI::App& app, const DeformOptionValues& values);

//! The options given on `app`, set from their text and checked together (resolve_options, with the keys given).
//! \throw UsageError as resolve_options.
DeformOptions deform_options_given(const CLI::App& app, const DeformOptionValues& values);

}  // namespace db
