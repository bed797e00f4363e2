// Issue 30 item 2: do the predictions hold (methods/run_prediction.h: peak RSS and init time from the symbolic
// analysis and the rates `deformbench advise --calibrate` measured on this machine)? For the cells of Table 2-1
// (tiers x lap, tf x dense, naive, structured; multifrontal, dense_llt for the dense build) and of the solver study
// (tiers x lap, tf x every backend with the structured build), `deformbench advise --quick` predicts each cell and
// measures it in a fresh child; this driver collects the rows, predicted against measured, into
//   results/predictions.csv   one row per cell (advise's columns, provenance, `study`, and for a cell measured
//                             several times - those under a second, --repeats - the median init's run with the
//                             spread: `repeats`, `init_s_min`, `init_s_max`)
// The report (python/dbtools/reports/predictions.py) sets them against the bands (peak +-25%, init +-50%).
// The tiers' edit: the whole mesh free, soft constraints, the 1% of the vertices nearest the highest one dragged up
// by a tenth of the mesh's height (TIER.edit beside the CSV). Options: --help.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/child_process.h"
#include "core/cli.h"
#include "core/csv.h"
#include "core/csv_reader.h"
#include "core/provenance.h"
#include "mesh/mesh_io.h"
#include "solvers/base/error.h"

namespace {

namespace fs = std::filesystem;
using namespace db;

struct Options {
  std::vector<std::string> tiers = {"hand=data/meshes/hand.off", "man=data/meshes/man.off",
                                    "armadillo=data/meshes/armadillo.off"};
  std::string study = "both", results = "results";
  double timeout_s = 600;
  int repeats = 3;             // measurements of a short cell
  double repeat_under_s = 1;  // a cell is short when its first init takes less
};

//! One advise call: a tier, a system, a build, the backends (empty: every applicable one).
struct Group {
  std::string study, tier, edit, method, build, backends;
};

//! TIER.edit in `dir` for the mesh at `path` (absolute, so the edit can live anywhere).
std::string write_tier_edit(const std::string& dir, const std::string& tier, const std::string& path) {
  const Mesh m = read_mesh(path);
  Eigen::Index top = 0;
  m.V.col(1).maxCoeff(&top);
  const double height = m.V.col(1).maxCoeff() - m.V.col(1).minCoeff();
  const std::string edit = fmt::format("{}/{}.edit", dir, tier);
  std::ofstream(edit) << fmt::format(
      "# exp_predictions: the whole mesh free, the 1% of the vertices nearest the highest one dragged up\n"
      "name = {}\nmesh = {}\nroi = all\nhandle = nearest:{},{},{},{}\ntransform = translate:0,{},0\n",
      tier, fs::absolute(path).string(), m.V(top, 0), m.V(top, 1), m.V(top, 2),
      std::max(1, m.num_vertices() / 100), height / 10);
  return edit;
}

std::vector<Group> groups(const Options& o, const std::string& dir) {
  std::vector<Group> g;
  for (const std::string& spec : o.tiers) {
    const auto eq = spec.find('=');
    if (eq == std::string::npos) throw UsageError(fmt::format("--tier {}: expected NAME=MESH", spec));
    const std::string tier = spec.substr(0, eq), edit = write_tier_edit(dir, tier, spec.substr(eq + 1));
    for (const char* method : {"lap", "tf"}) {
      if (o.study != "solvers") {
        g.push_back({"table_2_1", tier, edit, method, "dense", "dense_llt"});
        g.push_back({"table_2_1", tier, edit, method, "naive", "multifrontal"});
        g.push_back({"table_2_1", tier, edit, method, "structured", "multifrontal"});
      }
      if (o.study != "table_2_1") g.push_back({"solvers", tier, edit, method, "structured", ""});
    }
  }
  return g;
}

//! advise's rows for one group, with `study` and `tier` in front; empty when advise failed.
std::vector<CsvRow> run_group(const Group& g, const std::string& dir, double timeout_s) {
  const std::string exe = (fs::path(self_executable()).parent_path() / "deformbench").string();
  const std::string csv = fmt::format("{}/{}-{}-{}-{}.csv", dir, g.study, g.tier, g.method, g.build);
  std::vector<std::string> argv = {exe, "advise", g.edit, "--method", g.method, "--constraints", "soft", "--build",
                                   g.build, "--frames", "3", "--quick", "--timeout-s", fmt::format("{}", timeout_s),
                                   "--csv", csv};
  if (!g.backends.empty()) argv.insert(argv.end(), {"--backends", g.backends});
  fmt::print(stderr, "[predictions] {} {} {} {}\n", g.study, g.tier, g.method, g.build);
  const ChildRun c = run_child(argv, 0);
  std::fputs(c.err.c_str(), stderr);
  if (!c.ok()) {
    fmt::print(stderr, "[predictions] advise failed: {}\n", c.describe());
    return {};
  }
  std::vector<CsvRow> rows = read_csv(csv);
  for (CsvRow& r : rows) r["study"] = g.study;
  return rows;
}

double init_of(const CsvRow& r) {
  const auto it = r.find("init_s");
  return it == r.end() || it->second.empty() ? std::nan("") : std::stod(it->second);
}

std::string cell_of(const CsvRow& r) { return r.at("backend") + "/" + r.at("ordering"); }

//! The group's rows, each short cell (init under o.repeat_under_s) measured o.repeats times in all: its row is the
//! measurement with the median init (a cell of tens of milliseconds moves by half of it from run to run: one
//! measurement cannot tell that from the prediction's error), with `repeats`, `init_s_min` and `init_s_max`.
std::vector<CsvRow> measure_group(Group g, const std::string& dir, const Options& o) {
  std::vector<CsvRow> rows = run_group(g, dir, o.timeout_s);
  std::map<std::string, std::vector<CsvRow>> runs;
  std::set<std::string> short_backends;
  for (const CsvRow& r : rows) {
    runs[cell_of(r)].push_back(r);
    if (init_of(r) < o.repeat_under_s) short_backends.insert(r.at("backend"));
  }
  g.backends = fmt::format("{}", fmt::join(short_backends, ","));
  for (int k = 1; k < o.repeats && !short_backends.empty(); ++k)
    for (const CsvRow& r : run_group(g, dir, o.timeout_s))
      if (runs.count(cell_of(r)) && init_of(runs[cell_of(r)][0]) < o.repeat_under_s && !std::isnan(init_of(r)))
        runs[cell_of(r)].push_back(r);
  for (CsvRow& r : rows) {
    std::vector<CsvRow>& m = runs[cell_of(r)];
    std::stable_sort(m.begin(), m.end(), [](const CsvRow& a, const CsvRow& b) { return init_of(a) < init_of(b); });
    r = m[(m.size() - 1) / 2];
    r["repeats"] = std::to_string(m.size());
    r["init_s_min"] = m.front().at("init_s");
    r["init_s_max"] = m.back().at("init_s");
  }
  return rows;
}

int run(const Options& o) {
  const std::string dir = o.results + "/predictions";
  fs::create_directories(dir);
  CsvTable out;
  bool failed = false;
  const auto prov = provenance().columns();
  for (const Group& g : groups(o, dir)) {
    const std::vector<CsvRow> rows = measure_group(g, dir, o);
    failed = failed || rows.empty();
    for (const CsvRow& r : rows) {
      CsvTable::Row row;
      for (const auto& [k, v] : r)  // CsvTable appends this run's provenance; advise's own goes
        if (std::none_of(prov.begin(), prov.end(), [&](const auto& c) { return c.first == k; })) row.emplace_back(k, v);
      out.add(std::move(row));
    }
  }
  out.write(o.results + "/predictions.csv");
  fmt::print("wrote {}/predictions.csv ({} cells)\n", o.results, out.size());
  return failed ? 5 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"Predicted against measured peak RSS and init time for the Table 2-1 and solver-study cells"};
  app.add_option("--tier", o.tiers, "NAME=MESH, repeatable (default: the solver study's hand, man, armadillo)");
  app.add_option("--study", o.study, "which cells")->check(CLI::IsMember({"table_2_1", "solvers", "both"}))
      ->capture_default_str();
  app.add_option("--results", o.results, "output directory")->capture_default_str();
  app.add_option("--timeout-s", o.timeout_s, "wall-clock limit of each cell")->capture_default_str();
  app.add_option("--repeats", o.repeats, "measurements of a short cell; its row is the median init's")
      ->check(cli::Integer(1, 99))->capture_default_str();
  app.add_option("--repeat-under-s", o.repeat_under_s, "a cell is short when its first init takes less")
      ->check(cli::Real(0, 1e6))->capture_default_str();
  return cli::run(app, argc, argv, [&] { return run(o); });
}
