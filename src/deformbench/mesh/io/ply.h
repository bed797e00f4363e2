#pragma once
//! PLY (Stanford polygon file): ASCII or binary little-endian; the 'vertex' element's x, y, z properties (any scalar
//! type) and the 'face' element's 'vertex_indices' (or 'vertex_index') list and/or 'tristrips' strips; every other
//! element and property is skipped.
#include <ostream>
#include <string>

#include "mesh/mesh.h"

namespace db::io {

//! Parses PLY `data` (the header, then an ASCII or binary little-endian body) read from `path`. Binary errors name the
//! element; their line is where the header ended. Each element's count is checked against the bytes that follow before
//! anything is allocated.
//! \throw InputError "PATH: line N: cause" for the first problem (never a partially filled mesh).
Mesh read_ply(const std::string& path, const std::string& data);

//! Writes binary little-endian PLY: double x y z, faces as 'list uchar int vertex_indices'.
void write_ply(std::ostream& os, const Mesh& mesh);

}  // namespace db::io
