#include "harness/cell_pattern.h"

#include <algorithm>
#include <sstream>

#include <fmt/format.h>

#include "solvers/base/error.h"

namespace db::harness {
namespace {

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(s);
  while (std::getline(in, item, sep)) out.push_back(item);
  if (!s.empty() && s.back() == sep) out.emplace_back();
  return out;
}

std::vector<std::string> words(const std::string& s) {
  std::vector<std::string> out;
  std::istringstream in(s);
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

// "key=value" words; `what` names the line in messages.
KeyValues key_values(const std::string& text, const std::string& what) {
  KeyValues kv;
  for (const std::string& w : words(text)) {
    const auto eq = w.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == w.size())
      throw UsageError(fmt::format("{}: '{}' is not key=value", what, w));
    const std::string key = w.substr(0, eq);
    if (std::any_of(kv.begin(), kv.end(), [&](const auto& p) { return p.first == key; }))
      throw UsageError(fmt::format("{}: key '{}' given twice", what, key));
    kv.emplace_back(key, w.substr(eq + 1));
  }
  return kv;
}

// Splits "HEAD: REST" at the first colon.
std::pair<std::string, std::string> head_rest(const std::string& text, const std::string& what) {
  const auto colon = text.find(':');
  if (colon == std::string::npos) throw UsageError(fmt::format("{}: no ':'", what));
  return {text.substr(0, colon), text.substr(colon + 1)};
}

}  // namespace

std::vector<CellSpec> expand_cell_pattern(const std::string& text) {
  const std::string what = fmt::format("cell pattern '{}'", text);
  const auto [head, rest] = head_rest(text, what);
  const std::vector<std::string> kind_tiers = words(head);
  if (kind_tiers.size() != 2) throw UsageError(what + ": expected 'KIND TIER[,TIER...]:' before the colon");
  std::vector<std::pair<std::string, std::vector<std::string>>> axes{{"model", split(kind_tiers[1], ',')}};
  for (const auto& [key, values] : key_values(rest, what)) {
    if (key == "kind" || key == "model") throw UsageError(fmt::format("{}: '{}' is set before the colon", what, key));
    axes.emplace_back(key, split(values, ','));
  }
  std::vector<CellSpec> cells{CellSpec(kind_tiers[0])};
  for (const auto& [key, values] : axes) {
    std::vector<CellSpec> next;
    for (const CellSpec& c : cells)
      for (const std::string& v : values) {
        if (v.empty()) throw UsageError(fmt::format("{}: an empty value of '{}'", what, key));
        next.push_back(CellSpec(c).set(key, v));
      }
    cells = std::move(next);
  }
  return cells;
}

CellRule parse_cell_rule(const std::string& text) {
  const std::string what = fmt::format("cell rule '{}'", text);
  const auto [head, rest] = head_rest(text, what);
  CellRule r{key_values(head, what), key_values(rest, what), text};
  if (r.set.empty()) throw UsageError(what + ": nothing to set after the colon");
  return r;
}

bool rule_matches(const CellRule& rule, const CellSpec& spec) {
  return std::all_of(rule.when.begin(), rule.when.end(),
                     [&](const auto& kv) { return spec.has(kv.first) && spec.get(kv.first) == kv.second; });
}

bool apply_cell_rule(const CellRule& rule, CellSpec& spec, bool override) {
  if (!rule_matches(rule, spec)) return false;
  for (const auto& [key, value] : rule.set)
    if (override || !spec.has(key)) spec.set(key, value);
  return true;
}

}  // namespace db::harness
