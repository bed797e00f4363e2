#include "harness/cell.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <sstream>

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "harness/stats.h"
#include "harness/subprocess.h"

namespace db::harness {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string fmt_double(double v) { return std::isnan(v) ? "nan" : fmt::format("{}", v); }

double parse_double(const std::string& v) {
  if (v == "nan") return kNaN;
  char* end = nullptr;
  const double d = std::strtod(v.c_str(), &end);
  if (v.empty() || end != v.c_str() + v.size()) throw Error("not a number: " + v);
  return d;
}

template <class T>
auto find_named(T& list, const std::string& name) {
  return std::find_if(list.begin(), list.end(), [&](const auto& x) { return x.first == name; });
}

auto find_measure(std::vector<Measure>& m, const std::string& name) {
  return std::find_if(m.begin(), m.end(), [&](const Measure& x) { return x.name == name; });
}

}  // namespace

// ------------------------------------------------------------------------------------------------ CellSpec
CellSpec& CellSpec::set(const std::string& key, const std::string& value) {
  if (key.empty() || key.find_first_of("= \t\n") != std::string::npos)
    throw UsageError(fmt::format("cell spec: invalid key '{}'", key));
  auto it = find_named(items_, key);
  if (it != items_.end()) it->second = value;
  else items_.emplace_back(key, value);
  return *this;
}

CellSpec& CellSpec::set(const std::string& key, double value) { return set(key, fmt_double(value)); }

bool CellSpec::has(const std::string& key) const {
  return std::any_of(items_.begin(), items_.end(), [&](const auto& kv) { return kv.first == key; });
}

std::string CellSpec::get(const std::string& key) const {
  for (const auto& [k, v] : items_)
    if (k == key) return v;
  throw UsageError(fmt::format("cell spec ({}): missing key '{}'", kind(), key));
}

std::string CellSpec::get(const std::string& key, const std::string& fallback) const {
  for (const auto& [k, v] : items_)
    if (k == key) return v;
  return fallback;
}

double CellSpec::real(const std::string& key, double fallback, double min, double max) const {
  if (!has(key)) return fallback;
  const std::string s = get(key);
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(v))
    throw UsageError(fmt::format("cell spec: {}={} is not a finite number", key, s));
  if (v < min || v > max) throw UsageError(fmt::format("cell spec: {}={} is outside [{:g}, {:g}]", key, s, min, max));
  return v;
}

long long CellSpec::integer(const std::string& key, long long fallback, long long min, long long max) const {
  if (!has(key)) return fallback;
  const std::string s = get(key);
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(s.c_str(), &end, 10);
  if (s.empty() || end != s.c_str() + s.size() || errno == ERANGE)
    throw UsageError(fmt::format("cell spec: {}={} is not a whole number", key, s));
  if (v < min || v > max) throw UsageError(fmt::format("cell spec: {}={} is outside [{}, {}]", key, s, min, max));
  return v;
}

void CellSpec::check_keys(const std::vector<std::string>& known) const {
  for (const auto& [k, v] : items_)
    if (k != "kind" && std::find(known.begin(), known.end(), k) == known.end())
      throw UsageError(fmt::format("cell spec ({}): unknown key '{}' (known: {})", kind(), k, fmt::join(known, ", ")));
}

std::vector<std::string> CellSpec::to_args() const {
  std::vector<std::string> a;
  for (const auto& [k, v] : items_) a.push_back(k + "=" + v);
  return a;
}

CellSpec CellSpec::from_args(const std::vector<std::string>& args) {
  CellSpec s;
  for (const std::string& a : args) {
    const std::size_t eq = a.find('=');
    if (eq == std::string::npos) throw UsageError(fmt::format("cell spec: '{}' is not key=value", a));
    const std::string key = a.substr(0, eq);
    if (s.has(key)) throw UsageError(fmt::format("cell spec: key '{}' given twice", key));
    s.set(key, a.substr(eq + 1));
  }
  return s;
}

std::string CellSpec::text() const {
  std::string t;
  for (const auto& [k, v] : items_) t += (t.empty() ? "" : " ") + k + "=" + v;
  return t;
}

// ------------------------------------------------------------------------------------------------ CellResult
void CellResult::set(const std::string& name, double value, const std::string& unit) {
  auto it = find_measure(measures, name);
  if (it != measures.end()) {
    it->value = value;
    if (!unit.empty()) it->unit = unit;
  } else {
    measures.push_back({name, value, unit});
  }
}

double CellResult::get(const std::string& name) const {
  for (const Measure& m : measures)
    if (m.name == name) return m.value;
  return kNaN;
}

bool CellResult::has(const std::string& name) const {
  return std::any_of(measures.begin(), measures.end(), [&](const Measure& m) { return m.name == name; });
}

void CellResult::erase(const std::string& name) {
  measures.erase(std::remove_if(measures.begin(), measures.end(), [&](const Measure& m) { return m.name == name; }),
                 measures.end());
}

void CellResult::set_text(const std::string& name, const std::string& value) {
  auto it = find_named(texts, name);
  if (it != texts.end()) it->second = value;
  else texts.emplace_back(name, value);
}

std::string CellResult::text(const std::string& name) const {
  for (const auto& [k, v] : texts)
    if (k == name) return v;
  return "";
}

// ------------------------------------------------------------------------------------------------ the line
std::string encode_result(const CellResult& r) {
  std::ostringstream o;
  o << "DBCELL status=" << pct_encode(r.status) << " message=" << pct_encode(r.message);
  for (const auto& [k, v] : r.texts) o << " t." << pct_encode(k) << '=' << pct_encode(v);
  for (const Measure& m : r.measures) {
    o << " m." << pct_encode(m.name) << '=' << fmt_double(m.value);
    if (!m.unit.empty()) o << " u." << pct_encode(m.name) << '=' << pct_encode(m.unit);
  }
  return o.str();
}

CellResult decode_result(const std::string& out) {
  CellResult r;
  for (const auto& [k, v] : parse_result_line(out, "DBCELL")) {
    const std::string name = k.size() > 2 ? pct_decode(k.substr(2)) : "";
    if (k == "status") r.status = v;
    else if (k == "message") r.message = v;
    else if (k.rfind("t.", 0) == 0) r.set_text(name, v);
    else if (k.rfind("m.", 0) == 0) r.set(name, parse_double(v));
    else if (k.rfind("u.", 0) == 0) r.set(name, r.get(name), v);
    // Other keys are ignored: a newer child talking to an older parent.
  }
  return r;
}

namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() > suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

namespace {

void set_spread(CellResult& r, const std::string& name, const Spread& s) {
  r.set(name, s.median, "s");
  r.set(spread_name(name, "min"), s.min, "s");
  r.set(spread_name(name, "max"), s.max, "s");
  r.set(spread_name(name, "reps"), s.count, "count");
}

bool timed(const Measure& m) { return m.unit == "s" && ends_with(m.name, "_s"); }

// The spread of timed measure `name` over the runs: each run's own spread where it has one, else its value.
Spread spread_over(const std::vector<CellResult>& runs, const std::string& name) {
  std::vector<double> medians;
  Spread s{kNaN, kNaN, kNaN, 0};
  for (const CellResult& r : runs) {
    const double v = r.get(name);
    if (std::isnan(v)) continue;
    medians.push_back(v);
    const bool own = r.has(spread_name(name, "reps"));
    const double lo = own ? r.get(spread_name(name, "min")) : v, hi = own ? r.get(spread_name(name, "max")) : v;
    s.min = std::isnan(s.min) ? lo : std::min(s.min, lo);
    s.max = std::isnan(s.max) ? hi : std::max(s.max, hi);
    s.count += own ? static_cast<int>(r.get(spread_name(name, "reps"))) : 1;
  }
  s.median = median(medians);
  return s;
}

}  // namespace

void set_spread(CellResult& r, const std::string& name, const std::vector<double>& samples) {
  set_spread(r, name, spread(samples));
}

bool is_spread_of_measure(const CellResult& r, const std::string& name) {
  for (const std::string suffix : {"_min_s", "_max_s", "_reps"})
    if (ends_with(name, suffix) && r.has(name.substr(0, name.size() - suffix.size()) + "_s")) return true;
  return false;
}

CellResult median_of(const std::vector<CellResult>& runs) {
  if (runs.empty()) throw Error("median_of: no runs");
  CellResult m = runs.front();
  for (Measure& x : m.measures) {
    std::vector<double> v;
    for (const CellResult& r : runs)
      if (const double y = r.get(x.name); !std::isnan(y)) v.push_back(y);
    x.value = v.empty() ? kNaN : median(v);
  }
  for (const Measure& x : runs.front().measures)
    if (timed(x) && !is_spread_of_measure(runs.front(), x.name))
      if (const Spread s = spread_over(runs, x.name); s.count > 0) set_spread(m, x.name, s);
  return m;
}

std::vector<Measure> tidy_measures(const CellResult& r, const std::vector<MeasureDef>& defs) {
  std::vector<Measure> out;
  auto add = [&](const std::string& name, const std::string& unit, Keep keep) {
    const double v = r.get(name);
    if (keep == Keep::Always || !std::isnan(v) || (keep == Keep::IfRan && r.ok())) out.push_back({name, v, unit});
  };
  for (const MeasureDef& d : defs) {
    if (!d.name.empty() && d.name.back() == '*') {
      const std::string prefix = d.name.substr(0, d.name.size() - 1);
      for (const Measure& m : r.measures)
        if (m.name.rfind(prefix, 0) == 0) out.push_back({m.name, m.value, m.unit.empty() ? d.unit : m.unit});
      continue;
    }
    add(d.name, d.unit, d.keep);
    if (d.unit == "s" && d.spread) {
      add(spread_name(d.name, "min"), "s", d.keep);
      add(spread_name(d.name, "max"), "s", d.keep);
      add(spread_name(d.name, "reps"), "count", d.keep);
    }
  }
  return out;
}

}  // namespace db::harness
