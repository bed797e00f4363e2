#include "core/args.h"

#include <algorithm>
#include <sstream>

#include <fmt/format.h>

#include "core/error.h"

namespace db {

std::string Args::get(const std::string& k, const std::string& def) const {
  auto it = opts.find(k);
  return it == opts.end() ? def : it->second;
}

double Args::number(const std::string& k, double def) const {
  auto it = opts.find(k);
  if (it == opts.end()) return def;
  try {
    std::size_t pos = 0;
    const double v = std::stod(it->second, &pos);
    if (pos == it->second.size()) return v;
  } catch (const std::exception&) {
  }
  throw Error(fmt::format("{} expects a number, got '{}'", k, it->second));
}

std::vector<std::string> split_list(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::stringstream in(s);
  std::string t;
  while (std::getline(in, t, sep))
    if (!t.empty()) out.push_back(t);
  return out;
}

Args parse_args(int argc, char** argv, int first, const std::vector<std::string>& flags) {
  Args a;
  for (int i = first; i < argc; ++i) {
    const std::string s = argv[i];
    if (s.rfind("--", 0) != 0) {
      a.positional.push_back(s);
    } else if (std::find(flags.begin(), flags.end(), s) != flags.end()) {
      a.opts[s] = "1";
    } else {
      if (i + 1 >= argc) throw Error("option " + s + " needs a value");
      a.opts[s] = argv[++i];
    }
  }
  return a;
}

}  // namespace db
