#include "harness/mesh_source.h"

#include <algorithm>
#include <filesystem>
#include <iostream>

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "harness/runner.h"

namespace db::harness {
namespace {

namespace fs = std::filesystem;

int parse_level(const std::string& text, const std::string& whole) {
  if (text.empty() || text.size() > 1 || text[0] < '0' || text[0] > '8')
    throw UsageError(fmt::format("mesh '{}': Loop level '{}' is not a whole number in [0, 8]", whole, text));
  return text[0] - '0';
}

// "NAME=PATH+loopA..B" -> name, path (resolved), A, B (A = B = 0 without a suffix).
struct Parsed {
  std::string name, path;
  int first = 0, last = 0;
};

Parsed parse(const std::string& text, const std::string& base_dir) {
  Parsed p;
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
    throw UsageError(fmt::format("mesh '{}': expected NAME=PATH", text));
  p.name = text.substr(0, eq);
  p.path = text.substr(eq + 1);
  if (const std::size_t plus = p.path.rfind("+loop"); plus != std::string::npos) {
    const std::string levels = p.path.substr(plus + 5);
    p.path = p.path.substr(0, plus);
    const std::size_t dots = levels.find("..");
    p.first = parse_level(levels.substr(0, dots), text);
    p.last = dots == std::string::npos ? p.first : parse_level(levels.substr(dots + 2), text);
    if (p.last < p.first) throw UsageError(fmt::format("mesh '{}': empty level range", text));
  }
  if (p.path.empty()) throw UsageError(fmt::format("mesh '{}': empty path", text));
  if (!base_dir.empty() && fs::path(p.path).is_relative()) p.path = (fs::path(base_dir) / p.path).string();
  return p;
}

}  // namespace

MeshSource parse_mesh_source(const std::string& text, const std::string& base_dir) {
  const Parsed p = parse(text, base_dir);
  if (p.first != p.last) throw UsageError(fmt::format("mesh '{}': a level range names a series, not one mesh", text));
  return {p.name, p.path, p.first, ""};
}

std::vector<MeshSource> parse_mesh_series(const std::string& text, const std::string& base_dir) {
  const Parsed p = parse(text, base_dir);
  const std::string stem = fs::path(p.path).stem().string();
  std::vector<MeshSource> out;
  for (int k = p.first; k <= p.last; ++k)
    out.push_back({k == 0 ? stem : fmt::format("{}_loop{}", stem, k), p.path, k, p.name});
  return out;
}

std::string resolve_mesh(const MeshSource& s, const std::string& generated_dir, const std::string& cache_dir,
                         const std::string& exe) {
  if (!fs::exists(s.path)) throw InputError(fmt::format("mesh {} not found (run scripts/data.sh)", s.path));
  if (s.levels == 0) return s.path;
  const std::string name = fmt::format("{}_loop{}.off", fs::path(s.path).stem().string(), s.levels);
  if (const fs::path g = fs::path(generated_dir) / name; fs::exists(g)) return g.string();
  const fs::path out = fs::path(cache_dir) / name;
  if (fs::exists(out)) return out.string();
  fs::create_directories(cache_dir);
  std::cerr << fmt::format("[mesh] generating {} (Loop x{} of {})\n", out.string(), s.levels, s.path);
  CellSpec spec("loop_subdivide");
  spec.set("in", s.path).set("levels", s.levels).set("out", out.string());
  RunOptions o;
  o.timeout_s = 1800;
  const CellResult r = run_cell(exe, spec, o);
  if (!r.ok() || !fs::exists(out))
    throw InputError(fmt::format("could not generate {}: {}: {}", out.string(), r.exit, r.message));
  return out.string();
}

std::vector<MeshSource> select_sources(const std::vector<MeshSource>& sources, const std::vector<std::string>& only) {
  for (std::size_t i = 0; i < sources.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (sources[i].label == sources[j].label)
        throw UsageError(fmt::format("two tiers named '{}' ({} and {})", sources[i].label, sources[j].path, sources[i].path));
  for (const std::string& o : only)
    if (std::none_of(sources.begin(), sources.end(), [&](const MeshSource& s) { return s.label == o; }))
      throw UsageError(fmt::format("--only {}: no such tier", o));
  std::vector<MeshSource> out;
  for (const MeshSource& s : sources)
    if (only.empty() || std::find(only.begin(), only.end(), s.label) != only.end()) out.push_back(s);
  return out;
}

}  // namespace db::harness
