#pragma once
//! Minimal command-line parsing shared by the CLI and the experiment drivers: `--key value` options,
//! declared boolean flags, and positional arguments.
#include <map>
#include <string>
#include <vector>

namespace db {

struct Args {
  std::vector<std::string> positional;
  std::map<std::string, std::string> opts;

  bool has(const std::string& k) const { return opts.count(k) > 0; }
  std::string get(const std::string& k, const std::string& def) const;
  //! \throw Error when the value is not a number.
  double number(const std::string& k, double def) const;
};

//! "a,b,,c" -> {"a", "b", "c"}: the list form of options such as --tiers (empty items dropped).
std::vector<std::string> split_list(const std::string& s, char sep = ',');

//! Parses argv[first..argc). Options in `flags` take no value. \throw Error on an option missing its value.
Args parse_args(int argc, char** argv, int first, const std::vector<std::string>& flags = {});

}  // namespace db
