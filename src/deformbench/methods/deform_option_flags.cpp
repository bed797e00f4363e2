#include "methods/deform_option_flags.h"

#include <algorithm>

#include "core/cli.h"

namespace db {

const std::vector<std::string>& system_option_groups() {
  static const std::vector<std::string> g = {"Method", "LRI (--method lri)"};
  return g;
}

void add_deform_option_flags(CLI::App& app, DeformOptionValues& values, const std::vector<std::string>& groups,
                             const std::vector<std::string>& skip) {
  const DeformOptions defaults;
  for (const DeformOptionDef& def : deform_option_defs()) {
    if (!groups.empty() && std::find(groups.begin(), groups.end(), def.group) == groups.end()) continue;
    if (std::find(skip.begin(), skip.end(), def.key) != skip.end()) continue;
    CLI::Option* opt = nullptr;
    if (def.is_switch) {
      opt = app.add_flag_callback(def.flag, [&values, key = def.key] { values[key] = "1"; }, def.help);
    } else {
      opt = app.add_option(def.flag, values[def.key], def.help);
      opt->transform(def.choices.empty() ? CLI::Validator(def.check, "") : cli::OneOf(def.choices));
      if (!def.value_name.empty()) opt->type_name(def.value_name);
      if (const std::string value = def.get(defaults); !value.empty()) opt->default_str(value);
    }
    if (!def.group.empty()) opt->group(def.group);
  }
}

std::vector<std::string> deform_option_keys_given(const CLI::App& app, const DeformOptionValues& values) {
  std::vector<std::string> given;
  for (const DeformOptionDef& def : deform_option_defs()) {
    if (values.count(def.key) == 0) continue;  // not one of this app's (a switch: not given)
    if (const CLI::Option* opt = app.get_option_no_throw(def.flag); opt && opt->count() > 0) given.push_back(def.key);
  }
  return given;
}

DeformOptions deform_options_given(const CLI::App& app, const DeformOptionValues& values) {
  DeformOptions o;
  const std::vector<std::string> given = deform_option_keys_given(app, values);
  for (const std::string& key : given) deform_option_def(key).set(o, values.at(key));
  return resolve_options(o, given);
}

}  // namespace db
