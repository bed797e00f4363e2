#include "mesh/mesh_io.h"

#include <filesystem>

#include "solvers/base/atomic_file.h"
#include "solvers/base/error.h"
#include "mesh/io/common.h"
#include "mesh/io/obj.h"
#include "mesh/io/off.h"
#include "mesh/io/ply.h"
#include "mesh/io/stl.h"

namespace db {

namespace {

[[noreturn]] void unknown_extension(const std::string& path, const std::string& ext) {
  throw InputError(path + ": unknown mesh extension '" + ext + "' (expected .off, .ply, .obj or .stl)");
}

Mesh read_by_extension(const std::string& path) {
  const std::string ext = mesh_extension(path);
  if (ext == ".off") return io::read_off(path, io::read_file(path));
  if (ext == ".ply") return io::read_ply(path, io::read_file(path));
  if (ext == ".obj") return io::read_obj(path, io::read_file(path));
  if (ext == ".stl") return io::read_stl(path);
  unknown_extension(path, ext);
}

}  // namespace

const std::vector<std::string>& mesh_extensions() {
  static const std::vector<std::string> extensions = {".off", ".ply", ".obj", ".stl"};
  return extensions;
}

std::string mesh_extension(const std::string& path) {
  return io::lower(std::filesystem::path(path).extension().string());
}

Mesh read_mesh(const std::string& path) {
  Mesh m = read_by_extension(path);
  // Every format can spell an empty mesh (an empty OBJ, "OFF 0 0 0"); no command has a use for one.
  if (m.num_faces() == 0) throw InputError(path + ": the mesh is empty (no faces)");
  return m;
}

void write_mesh(const std::string& path, const Mesh& mesh, const MeshWriteOptions& options) {
  const std::string ext = mesh_extension(path);
  if (ext == ".off") {
    write_atomically(path, [&](std::ostream& os) { io::write_off(os, mesh); });
  } else if (ext == ".obj") {
    write_atomically(path, [&](std::ostream& os) { io::write_obj(os, mesh); });
  } else if (ext == ".ply") {
    write_atomically(path, [&](std::ostream& os) { io::write_ply(os, mesh); }, true);
  } else if (ext == ".stl") {
    io::check_stl_writable(path, mesh, options.stl);
    write_atomically(path, [&](std::ostream& os) { io::write_stl(os, mesh, options.stl); }, true);
  } else {
    unknown_extension(path, ext);
  }
}

}  // namespace db
