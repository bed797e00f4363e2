#pragma once
//! The meshes of an experiment's grid as a config file or a command line names them:
//!   NAME=PATH               a mesh file
//!   NAME=PATH+loopK         PATH Loop-subdivided K times
//!   NAME=PATH+loopA..B      (series) one mesh per level A..B, labelled STEM (level 0) and STEM_loopK
//! so that a user runs a driver on their own mesh without recompiling.
#include <string>
#include <vector>

namespace db::harness {

struct MeshSource {
  std::string label;  //!< the tier / model label of result rows
  std::string path;   //!< the mesh file, or the base of the Loop levels
  int levels = 0;     //!< Loop subdivision levels applied to `path`
  std::string series;  //!< series name (parse_mesh_series), "" for a tier
};

//! Parses "NAME=PATH[+loopK]"; a relative PATH is taken relative to `base_dir` (unless it is ""). \throw
//! UsageError for a missing name or path, a malformed level or one above 8.
MeshSource parse_mesh_source(const std::string& text, const std::string& base_dir);
//! Parses "NAME=PATH+loopA..B" (or +loopK: A = B = K) into one source per level.
std::vector<MeshSource> parse_mesh_series(const std::string& text, const std::string& base_dir);

//! The file to read for `s`: PATH itself without levels; else GENERATED/STEM_loopK.off when the data step made
//! it, else CACHE/STEM_loopK.off, generated there first (in a child process of `exe`, harness/runner.h's
//! loop_subdivide kind) when missing. \throw InputError when the mesh is missing or cannot be generated.
std::string resolve_mesh(const MeshSource& s, const std::string& generated_dir, const std::string& cache_dir,
                         const std::string& exe);

//! Keeps the sources whose label is in `only` (all of them when `only` is empty), in the order of `sources`.
//! \throw UsageError for a label of `only` that names no source, or two sources of one label.
std::vector<MeshSource> select_sources(const std::vector<MeshSource>& sources, const std::vector<std::string>& only);

}  // namespace db::harness
