#pragma once
// What coat and transplant share on the command line: two meshes, a region of each, --out and --csv, checked
// before any mesh is read; the meshes and regions loaded; the outputs written together.
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "applications/application_measures.h"
#include "mesh/mesh.h"

namespace db::commands {

struct PatchArgs {
  std::string source, target, out, csv, source_region = "all", target_region = "all";
};

//! SOURCE, TARGET, --out, --csv, --source-region, --target-region.
void add_patch_options(CLI::App& app, PatchArgs& a, const std::string& source_help);

struct PatchInputs {
  Mesh source, target;
  std::vector<int> source_region, target_region;
};

//! Checks the outputs (usage errors, exit 1), then reads and validates both meshes (manifold: the patches must be
//! disks) and selects the regions (exit 2 naming the problem).
PatchInputs load_patch_inputs(const CLI::App& app, const PatchArgs& a);

//! Writes `result` to --out and, with --csv, one row (the command, the meshes, the regions and the backend, then
//! `values`, provenance appended), all or nothing; prints `values`.
void write_outputs(const PatchArgs& a, const std::string& command, const PatchInputs& in, const std::string& backend,
                   const Mesh& result, const NamedValues& values);

}  // namespace db::commands
