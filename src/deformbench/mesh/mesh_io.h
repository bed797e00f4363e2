#pragma once
//! Mesh files: OFF, PLY (ASCII and binary little-endian), OBJ and STL (ASCII and binary), one reader and writer per
//! format under mesh/io/. Reading is strict: a malformed file is an InputError naming the file, the line (or the
//! element or triangle) and the problem, never a partially filled mesh.
#include <string>
#include <vector>

#include "mesh/mesh.h"

namespace db {

//! How write_mesh encodes an .stl file.
enum class StlEncoding {
  Ascii,   //!< each coordinate as the shortest text that reads back to the same double: exact (the default)
  Binary,  //!< 32-bit floats, as the format defines: each coordinate rounded to the nearest float
};

//! Choices of the writers that the extension does not make.
struct MeshWriteOptions {
  StlEncoding stl = StlEncoding::Ascii;
};

//! The extensions read_mesh reads and write_mesh writes: .off, .ply, .obj, .stl.
const std::vector<std::string>& mesh_extensions();
//! The extension read_mesh and write_mesh go by: `path`'s, lower case with the dot (".stl").
std::string mesh_extension(const std::string& path);

//! Reads by extension (.off, .ply, .obj, .stl; case-insensitive); polygons with more than three corners are
//! fan-triangulated. Sets mesh.name to the file stem. Does not call validate_mesh().
//! \throw InputError unreadable file, unknown extension, malformed content, an empty mesh (no faces).
Mesh read_mesh(const std::string& path);

//! Writes by extension (.off, .ply binary little-endian, .obj, .stl as options.stl says) atomically (temp file +
//! rename): a failure leaves no file. \throw InputError for a mesh the format cannot hold (STL: see mesh/io/stl.h),
//! checked before anything is written; Error when the file cannot be written.
void write_mesh(const std::string& path, const Mesh& mesh, const MeshWriteOptions& options = {});

}  // namespace db
