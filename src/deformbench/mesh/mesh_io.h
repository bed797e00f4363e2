#pragma once
//! Mesh files: OFF, PLY (ASCII and binary little-endian) and OBJ, one reader and writer per format under mesh/io/.
//! Reading is strict: a malformed file is an InputError naming the file, the line or element and the problem, never
//! a partially filled mesh.
#include <string>

#include "mesh/mesh.h"

namespace db {

//! Reads by extension (.off, .ply, .obj); polygons with more than three corners are fan-triangulated.
//! Sets mesh.name to the file stem. Does not call validate_mesh().
//! \throw InputError unreadable file, unknown extension, malformed content.
Mesh read_mesh(const std::string& path);

//! Writes by extension (.off, .ply binary little-endian, .obj) atomically (temp file + rename).
void write_mesh(const std::string& path, const Mesh& mesh);

}  // namespace db
