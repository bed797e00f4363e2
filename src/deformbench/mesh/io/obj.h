#pragma once
//! Wavefront OBJ: 'v x y z [w | r g b]' vertices and 'f' faces whose corners are 'a', 'a/b', 'a//c' or 'a/b/c'
//! (1-based; negative counts back from the last vertex so far); vt, vn, vp, o, g, s, usemtl, mtllib, l and p statements
//! are skipped, any other statement is an error.
#include <ostream>
#include <string>

#include "mesh/mesh.h"

namespace db::io {

//! Parses OBJ text `data` read from `path`. Polygons are fan-triangulated.
//! \throw InputError "PATH: line N: cause" for the first problem (never a partially filled mesh).
Mesh read_obj(const std::string& path, const std::string& data);

//! Writes 'v' lines (shortest exact text for each double) and 1-based 'f' triangles.
void write_obj(std::ostream& os, const Mesh& mesh);

}  // namespace db::io
