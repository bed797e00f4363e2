#pragma once
//! OFF (Object File Format): a header keyword [ST][C][N]OFF (optional), the counts line '#vertices #faces [#edges]',
//! one vertex a line, then one polygon a line ('n i0 .. in-1', 0-based, an optional face colour after); '#' starts a
//! comment.
#include <ostream>
#include <string>

#include "mesh/mesh.h"

namespace db::io {

//! Parses OFF text `data` read from `path` (for messages and the mesh name). Colours, normals and texture coordinates
//! are skipped; polygons are fan-triangulated; declared counts are checked against the bytes that follow before
//! anything is allocated.
//! \throw InputError "PATH: line N: cause" for the first problem (never a partially filled mesh).
Mesh read_off(const std::string& path, const std::string& data);

//! Writes 'OFF', the counts and one triangle a line; coordinates as the shortest text that reads back to the same
//! double.
void write_off(std::ostream& os, const Mesh& mesh);

}  // namespace db::io
