#include "patch_args.h"

#include <cmath>

#include <fmt/format.h>

#include "solvers/base/atomic_file.h"
#include "core/cli.h"
#include "core/csv.h"
#include "solvers/base/error.h"
#include "core/provenance.h"
#include "edit/selection.h"
#include "mesh/mesh_io.h"

namespace db::commands {
namespace {

const char* kRegionForms = "all | sphere:cx,cy,cz,r | box:x0,y0,z0,x1,y1,z1 | kring:v,k | nearest:x,y,z,count | "
                           "indices:FILE";

// The files a region reads (indices:FILE), so no output overwrites them.
void add_region_file(const std::string& spec, std::vector<std::string>& inputs) {
  if (spec.rfind("indices:", 0) == 0) inputs.push_back(spec.substr(8));
}

Mesh load(const std::string& path) {
  Mesh m = read_mesh(path);
  validate_mesh(m, Manifold::Required);
  return m;
}

std::vector<int> select_region(const Mesh& m, const char* option, const std::string& spec) {
  std::vector<int> region = select_by_spec(m, spec);
  if (region.empty()) throw InputError(fmt::format("{} {} selects no vertex of {}", option, spec, m.name));
  return region;
}

}  // namespace

void add_patch_options(CLI::App& app, PatchArgs& a, const std::string& source_help) {
  app.add_option("source", a.source, source_help)->type_name("SOURCE")->required();
  app.add_option("target", a.target, "the target mesh (.off, .ply, .obj)")->type_name("TARGET")->required();
  app.add_option("--out", a.out, "the resulting target mesh (.off, .ply, .obj or .stl); written only if the run succeeds")
      ->type_name("FILE")->required();
  app.add_option("--csv", a.csv, "also write one CSV row (.csv) of the measurements with provenance")
      ->type_name("FILE");
  app.add_option("--source-region", a.source_region,
                 fmt::format("the source patch: the faces whose corners it selects, a disk ({})", kRegionForms))
      ->type_name("SPEC")->capture_default_str();
  app.add_option("--target-region", a.target_region, "the target patch, the same forms (a disk)")
      ->type_name("SPEC")->capture_default_str();
}

PatchInputs load_patch_inputs(const CLI::App& app, const PatchArgs& a) {
  std::vector<std::string> inputs = {a.source, a.target};
  add_region_file(a.source_region, inputs);
  add_region_file(a.target_region, inputs);
  cli::check_output("--out", a.out, mesh_extensions(), inputs);
  if (app.count("--csv") > 0) cli::check_output("--csv", a.csv, {".csv"}, inputs);
  PatchInputs in;
  in.source = load(a.source);
  in.target = a.target == a.source ? in.source : load(a.target);
  in.source_region = select_region(in.source, "--source-region", a.source_region);
  in.target_region = select_region(in.target, "--target-region", a.target_region);
  return in;
}

void write_outputs(const PatchArgs& a, const std::string& command, const PatchInputs& in, const std::string& backend,
                   const Mesh& result, const NamedValues& values) {
  StagedOutputs outputs;
  write_mesh(outputs.stage(a.out), result);
  CsvTable::Row row = {{"app", command},
                       {"source", in.source.name},
                       {"target", in.target.name},
                       {"source_region", a.source_region},
                       {"target_region", a.target_region},
                       {"backend", backend}};
  for (const auto& [name, value] : values) {
    if (std::isnan(value)) {  // not measured by this command: an empty cell, nothing printed
      row.emplace_back(name, "");
      continue;
    }
    row.emplace_back(name, num(value));
    fmt::print("{} {}\n", name, num(value));
  }
  if (!a.csv.empty()) {
    CsvTable csv;
    csv.add(row);
    csv.write(outputs.stage(a.csv));
  }
  outputs.commit();
  fmt::print("{}\nwrote {}{}\n", provenance_summary(), a.out, a.csv.empty() ? "" : " and " + a.csv);
}

}  // namespace db::commands
