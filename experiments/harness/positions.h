#pragma once
//! Vertex positions a cell hands to its parent through a scratch file, for measures that compare cells (a
//! backend's result against the reference backend's, an LRI frame strategy's against another's): each cell
//! stays independent of the others, the parent compares after the cells have run.
#include <string>

#include "solvers/base/types.h"

namespace db::harness {

//! Writes #V x 3 positions (binary, atomically). \throw Error when the file cannot be written.
void write_positions(const std::string& path, const Points& V);
//! \throw InputError when the file is missing, truncated or not a positions file.
Points read_positions(const std::string& path);

}  // namespace db::harness
