// The LSE report's two other applications on bundled data (data/experiments/applications.toml): coating transfer
// (the BS08 plane's bumps onto the CGAL bunny and a procedural plane) and transplanting (a bump of the BS08 plane
// grafted onto the bunny; a fine bumpy patch onto a coarse plane; a patch grafted back where it was cut, which
// must leave the surface as it was). One row
// per case: sizes, phase times, detail preservation, boundary continuity (applications/application_measures.h)
// and the cell's peak RSS; each case is a cell (kind "application") in a fresh child process. With --meshes the
// cells write CASE__{source,target,result}.ply and CASE__{source_patch,patch,result_patch}.txt (the vertex ids of
// the source and target patches, and of the transferred or grafted part of the result) for python/dbtools/plots/applications.py.
//
// Cases, "NAME: APP key=value ..." with APP coat or transplant; keys source=, target= (a mesh path relative to
// --data, or plane:NX:NY:SIZE:HEIGHT:BUMPS), source_region=, target_region= (the selection forms of .edit files,
// default all), smooth_weight=, amplitude=, map=, encoding= (coat), zone= (transplant); coat's target=self is the
// source's own smooth version (the self-coating, whose result must be the source: column self_error); map=all and
// encoding=all make one cell per value (the case's name suffixed with the values), so each alternative is measured.
// A case whose mesh is absent is skipped; a case that fails is a row with its status, and the driver then exits
// with kCellsFailedExit (harness/driver.h).
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>

#include <fmt/format.h>

#include "applications/application_measures.h"
#include "core/cli.h"
#include "core/csv.h"
#include "solvers/base/error.h"
#include "core/provenance.h"
#include "solvers/base/resources.h"
#include "core/timer.h"
#include "edit/selection.h"
#include "harness/driver.h"
#include "harness/runner.h"
#include "harness/subprocess.h"
#include "mesh/mesh_io.h"
#include "mesh/procedural.h"

namespace fs = std::filesystem;
using namespace db;
using namespace db::harness;

namespace {

const std::vector<std::string> kCaseKeys = {"source", "target", "source_region", "target_region", "smooth_weight",
                                            "amplitude", "zone", "map", "encoding"};

struct Options {
  std::string data = "data", out = "results/applications.csv", meshes;
  std::vector<std::string> cases;
  double cell_timeout_s = 600;
  bool dry_run = false;
};

void define_options(CLI::App& app, Options& o) {
  add_config_option(app, "data/experiments/applications.toml");
  app.add_option("--data", o.data, "data directory; mesh paths of the cases are inside it")->capture_default_str();
  app.add_option("--out", o.out, "the CSV")->capture_default_str();
  app.add_option("--meshes", o.meshes, "write each case's source, target and result here (for the renders)");
  app.add_option("--case", o.cases, "a case: \"NAME: coat|transplant source=... target=... [key=value ...]\"");
  app.add_option("--cell-timeout-s", o.cell_timeout_s, "kill a cell after this")->check(cli::Real(1, 1e7))
      ->capture_default_str();
  app.add_flag("--dry-run", o.dry_run, "print the grid's cells (one spec a line) and exit");
}

// "NAME: APP key=value ..." -> the cell's spec (paths resolved against --data); "" name when a mesh is absent.
CellSpec parse_case(const std::string& text, const std::string& data, std::string& name) {
  const std::size_t colon = text.find(':');
  if (colon == std::string::npos || colon == 0) throw UsageError(fmt::format("case '{}': expected NAME: APP ...", text));
  name = text.substr(0, colon);
  std::istringstream in(text.substr(colon + 1));
  std::string app;
  in >> app;
  if (app != "coat" && app != "transplant")
    throw UsageError(fmt::format("case '{}': '{}' is not coat or transplant", text, app));
  CellSpec s("application");
  s.set("name", name).set("app", app);
  for (std::string kv; in >> kv;) {
    const std::size_t eq = kv.find('=');
    if (eq == std::string::npos) throw UsageError(fmt::format("case '{}': '{}' is not key=value", text, kv));
    std::string key = kv.substr(0, eq), value = kv.substr(eq + 1);
    if (std::find(kCaseKeys.begin(), kCaseKeys.end(), key) == kCaseKeys.end())
      throw UsageError(fmt::format("case '{}': unknown key {} (known: {})", text, key, fmt::join(kCaseKeys, ", ")));
    if ((key == "source" || key == "target") && value.rfind("plane:", 0) != 0 && value != "self") {
      value = (fs::path(data) / value).string();
      if (!fs::exists(value)) {
        std::cerr << fmt::format("[applications] skipping {}: {} not found (run scripts/data.sh)\n", name, value);
        name.clear();
      }
    }
    s.set(key, value);
  }
  if (!s.has("source") || !s.has("target")) throw UsageError(fmt::format("case '{}': needs source= and target=", text));
  return s;
}

// A mesh file, or plane:NX:NY:SIZE:HEIGHT:BUMPS (mesh/procedural.h), validated as a manifold.
Mesh load_mesh(const std::string& spec) {
  Mesh m;
  if (spec.rfind("plane:", 0) == 0) {
    std::vector<double> a;
    std::istringstream in(spec.substr(6));
    for (std::string t; std::getline(in, t, ':');) a.push_back(std::stod(t));
    if (a.size() != 5) throw UsageError(fmt::format("{}: expected plane:NX:NY:SIZE:HEIGHT:BUMPS", spec));
    m = make_bumpy_plane(static_cast<int>(a[0]), static_cast<int>(a[1]), a[2], a[3], static_cast<int>(a[4]));
  } else {
    m = read_mesh(spec);
  }
  validate_mesh(m, Manifold::Required);
  return m;
}

void write_ids(const std::string& path, const std::vector<int>& ids) {
  std::ofstream out(path);
  for (int v : ids) out << v << "\n";
  if (!out) throw Error("cannot write " + path);
}

// `result_patch`: the result's vertices that the render colours as the transferred or grafted part.
void write_meshes(const CellSpec& s, const Mesh& source, const Mesh& target, const Mesh& result, const DiskPatch& sp,
                  const DiskPatch& p, const std::vector<int>& result_patch) {
  const fs::path dir = s.get("meshes");
  const std::string stem = (dir / s.get("name")).string() + "__";
  write_mesh(stem + "source.ply", source);
  write_mesh(stem + "target.ply", target);
  write_mesh(stem + "result.ply", result);
  write_ids(stem + "patch.txt", p.parent);
  write_ids(stem + "source_patch.txt", sp.parent);
  write_ids(stem + "result_patch.txt", result_patch);
}

// The graft in the result: the source patch's vertices and the hole's loop (so the band's faces count too).
std::vector<int> graft_vertices(const Transplant& t) {
  std::vector<int> ids = t.source_in_result;
  for (int l : t.patch.boundary)  // kept is ascending in the target's ids
    ids.push_back(static_cast<int>(std::lower_bound(t.kept.begin(), t.kept.end(), t.patch.parent[l]) - t.kept.begin()));
  return ids;
}

// The application's measures; a name ending in "_s" is a time (unit "s", so that it gets its spread).
void set_measures(CellResult& r, const NamedValues& values) {
  for (const auto& [k, v] : values) r.set(k, v, k.size() > 2 && k.compare(k.size() - 2, 2, "_s") == 0 ? "s" : "");
}

// Coating transfer; a self-coating (target=self) also measures how far the result is from the source, over the
// source patch's bounding-box diagonal (NaN otherwise).
void measure_coat(const CellSpec& s, const Mesh& source, const std::vector<int>& sr, CellResult& r) {
  CoatingOptions o;
  o.smooth_weight = s.real("smooth_weight", o.smooth_weight, 1e-6, 1e3);
  o.amplitude = s.real("amplitude", o.amplitude, -1e3, 1e3);
  o.map = parse_enum<DiskMap>(s.get("map", to_string(o.map)));
  o.encoding = parse_enum<DetailEncoding>(s.get("encoding", to_string(o.encoding)));
  Timer t;
  const Coating c = extract_coating(source, sr, o);
  const bool self = s.get("target") == "self";
  const Mesh target = self ? own_smooth_version(source, c) : load_mesh(s.get("target"));
  const std::vector<int> tr = self ? sr : select_by_spec(target, s.get("target_region", "all"));
  const CoatedTarget res = transfer_coating(c, target, tr, o);
  set_measures(r, coat_measures(c, res, target, t.seconds()));
  double self_error = std::numeric_limits<double>::quiet_NaN();
  if (self) {
    self_error = 0;
    for (int v : c.patch.parent) self_error = std::max(self_error, (res.result.V.row(v) - source.V.row(v)).norm());
    self_error /= bbox_diagonal(c.patch.mesh.V);
  }
  r.set("self_error", self_error);
  r.set_text("backend", res.solve.system.backend);
  if (s.has("meshes")) write_meshes(s, source, target, res.result, c.patch, res.patch, res.patch.parent);
}

CellResult measure_application(const CellSpec& s) {
  s.check_keys({"name", "app", "meshes", "source", "target", "source_region", "target_region", "smooth_weight",
                "amplitude", "zone", "map", "encoding"});
  const Mesh source = load_mesh(s.get("source"));
  const std::vector<int> sr = select_by_spec(source, s.get("source_region", "all"));
  CellResult r;
  if (s.get("app") == "coat") {
    measure_coat(s, source, sr, r);
  } else {
    const Mesh target = load_mesh(s.get("target"));
    const std::vector<int> tr = select_by_spec(target, s.get("target_region", "all"));
    TransplantOptions o;
    o.zone = s.real("zone", o.zone, 0.01, 1);
    Timer t;
    const Transplant res = transplant_patch(source, sr, target, tr, o);
    set_measures(r, transplant_measures(res, target, t.seconds()));
    r.set("self_error", std::numeric_limits<double>::quiet_NaN());
    r.set_text("backend", res.solve.system.backend);
    if (s.has("meshes")) write_meshes(s, source, target, res.result, res.source_patch, res.patch, graft_vertices(res));
  }
  r.set("source_vertices", source.num_vertices());
  r.set("peak_rss_bytes", static_cast<double>(peak_rss_bytes()), "bytes");
  return r;
}

// One row a case; `shape` (a cell that ran) gives a failed cell's columns, left empty.
void add_row(CsvTable& csv, const CellSpec& s, const CellResult& r, const CellResult* shape) {
  CsvTable::Row row = {{"case", s.get("name")},
                       {"app", s.get("app")},
                       {"source", fs::path(s.get("source")).filename().string()},
                       {"target", fs::path(s.get("target")).filename().string()},
                       {"source_region", s.get("source_region", "all")},
                       {"target_region", s.get("target_region", s.get("target") == "self" ? s.get("source_region", "all") : "all")},
                       {"map", s.get("app") == "coat" ? s.get("map", to_string(CoatingOptions{}.map)) : ""},
                       {"encoding", s.get("app") == "coat" ? s.get("encoding", to_string(CoatingOptions{}.encoding)) : ""},
                       {"backend", r.text("backend")},
                       {"status", r.status},
                       {"message", r.message}};
  const CellResult& columns = r.ok() || !shape ? r : *shape;
  for (const Measure& m : columns.measures)
    if (m.name != "peak_rss_bytes" && m.name != "cell_wall_s" && m.name != "load_avg_1m" && m.name != "runs" &&
        m.name != "ru_maxrss_bytes" && m.name != "parent_rss_bytes" && !is_spread_of_measure(columns, m.name)) {
      const double v = r.get(m.name);
      row.emplace_back(m.name, std::isnan(v) ? "" : num(v));
      if (m.unit == "s") add_spread_columns(row, r, m.name);
    }
  row.emplace_back("process_peak_rss_bytes", num(r.get("peak_rss_bytes")));
  csv.add(row);
}

// A coat case with map=all or encoding=all as one cell per combination of the values, named NAME.MAP.ENCODING.
std::vector<CellSpec> expand_alternatives(const CellSpec& s) {
  if (s.get("app") != "coat" || (s.get("map", "") != "all" && s.get("encoding", "") != "all")) return {s};
  const auto values = [&](const std::string& key, const std::vector<std::string>& all, const std::string& dflt) {
    const std::string v = s.get(key, dflt);
    return v == "all" ? all : std::vector<std::string>{v};
  };
  std::vector<CellSpec> out;
  for (const std::string& m : values("map", enum_names<DiskMap>(), to_string(CoatingOptions{}.map)))
    for (const std::string& e : values("encoding", enum_names<DetailEncoding>(), to_string(CoatingOptions{}.encoding))) {
      CellSpec c = s;
      c.set("map", m).set("encoding", e).set("name", s.get("name") + "." + m + "." + e);
      out.push_back(c);
    }
  return out;
}

int run(Options& o) {
  cli::check_output("--out", o.out, {".csv"});
  if (!o.meshes.empty()) check_output_dir("--meshes", o.meshes);
  std::vector<CellSpec> grid;
  for (const std::string& text : o.cases) {
    std::string name;
    CellSpec s = parse_case(text, o.data, name);
    if (name.empty()) continue;
    if (!o.meshes.empty()) s.set("meshes", o.meshes);
    for (const CellSpec& c : expand_alternatives(s)) grid.push_back(c);
  }
  if (grid.empty()) throw InputError("no application case found (--case, or a --config that lists cases)");
  if (o.dry_run) {
    for (const CellSpec& s : grid) std::cout << s.text() << "\n";
    return 0;
  }
  if (!o.meshes.empty()) fs::create_directories(o.meshes);
  std::cerr << "[applications] " << provenance_summary() << "\n";
  CsvTable csv;
  RunOptions ro;
  ro.timeout_s = o.cell_timeout_s;
  FailedCells failed("applications");
  std::vector<CellResult> results;
  for (const CellSpec& s : grid) {
    results.push_back(run_cell(self_executable(), s, ro));
    const CellResult& r = results.back();
    failed.note(s.text(), r);
    if (!r.ok()) {
      std::cerr << fmt::format("[applications] {}: {}: {} ({})\n", s.get("name"), r.status, r.message, r.exit);
      continue;
    }
    std::cerr << fmt::format("[applications] {:24s} patch {:6.0f} v  total {:.3f} s  detail error {:.3g}  seam max "
                             "{:.1f} -> {:.1f} deg\n",
                             s.get("name"), r.get("patch_vertices"), r.get("total_s"), r.get("detail_error"),
                             r.get("seam_max_deg_before"), r.get("seam_max_deg_after"));
  }
  // The rows of the cells that ran set the columns; a failed cell's row has them empty.
  const auto ran = std::find_if(results.begin(), results.end(), [](const CellResult& r) { return r.ok(); });
  const CellResult* shape = ran == results.end() ? nullptr : &*ran;
  for (std::size_t i = 0; i < grid.size(); ++i) add_row(csv, grid[i], results[i], shape);
  csv.write(o.out);
  std::cerr << "[applications] wrote " << o.out << "\n";
  return failed.exit_code();
}

}  // namespace

int main(int argc, char** argv) {
  if (is_cell_invocation(argc, argv)) return cell_main(argc, argv, {{"application", measure_application}});
  CLI::App app("Coating transfer and transplanting on bundled data, each case in a fresh child process.",
               "exp_applications");
  Options o;
  define_options(app, o);
  return cli::run(app, argc, argv, [&] { return run(o); });
}
