#include "harness/toml_config.h"

#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <toml++/toml.h>

namespace db::harness {
namespace {

CLI::ParseError config_error(const std::string& file, const toml::source_region& where, const std::string& what) {
  return CLI::ParseError(fmt::format("{}:{}:{}: {}", file, where.begin.line, where.begin.column, what),
                         CLI::ExitCodes::ConversionError);
}

// A scalar as the option's text: strings as written, numbers and booleans as TOML spells them.
std::string scalar_text(const toml::node& n, const std::string& file, const std::string& key) {
  if (const auto* s = n.as_string()) return s->get();
  if (n.is_integer() || n.is_floating_point() || n.is_boolean()) {
    std::ostringstream os;
    n.visit([&os](const auto& v) { os << v; });
    return os.str();
  }
  throw config_error(file, n.source(), fmt::format("'{}': a value must be a string, a number, a boolean or a list "
                                                   "of them", key));
}

class StrictToml : public CLI::Config {
 public:
  StrictToml(const CLI::App* app, const CLI::Option* config) : app_(app), config_(config) {}

  std::string to_config(const CLI::App*, bool, bool, std::string) const override { return {}; }

  std::vector<CLI::ConfigItem> from_config(std::istream& input) const override {
    const std::string file = config_ && config_->count() > 0 ? config_->as<std::string>()
                             : config_                        ? config_->get_default_str()
                                                              : std::string("config");
    toml::table table;
    try {
      table = toml::parse(input, file);
    } catch (const toml::parse_error& e) {
      throw config_error(file, e.source(), std::string(e.description()));
    }
    std::vector<CLI::ConfigItem> items;
    for (const auto& [key, node] : table) {
      CLI::ConfigItem item;
      item.name = std::string(key.str());
      if (app_->get_option_no_throw("--" + item.name) == nullptr)
        throw config_error(file, node.source(), fmt::format("'{}' is no option of {}", item.name,
                                                            app_->get_name()));
      if (const auto* list = node.as_array()) {
        for (const toml::node& element : *list) item.inputs.push_back(scalar_text(element, file, item.name));
      } else {
        item.inputs.push_back(scalar_text(node, file, item.name));
      }
      items.push_back(std::move(item));
    }
    return items;
  }

 private:
  const CLI::App* app_;
  const CLI::Option* config_;
};

}  // namespace

std::shared_ptr<CLI::Config> strict_toml_config(const CLI::App& app, const CLI::Option* config) {
  return std::make_shared<StrictToml>(&app, config);
}

}  // namespace db::harness
