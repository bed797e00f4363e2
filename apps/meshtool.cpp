// meshtool: mesh utilities for the data step (scripts/data.sh) and for inspecting inputs.
//   meshtool info FILE [--validate]          name, #V, #F and a content checksum (optionally validate_mesh)
//   meshtool subdivide IN OUT LEVELS         Loop subdivision (OpenMesh)
//   meshtool convert IN OUT                  re-write in the format given by OUT's extension
//   meshtool generate cylinder|bar|plane OUT [key=value ...]
#include <cstdint>
#include <cstring>
#include <iostream>
#include <map>
#include <string>

#include <fmt/format.h>

#include "core/error.h"
#include "mesh/mesh.h"
#include "mesh/mesh_io.h"
#include "mesh/procedural.h"
#include "mesh/subdivision.h"

namespace {

using namespace db;

const char* kUsage =
    "usage: meshtool info FILE [--validate]\n"
    "       meshtool subdivide IN OUT LEVELS\n"
    "       meshtool convert IN OUT\n"
    "       meshtool generate cylinder OUT [rings=41 segments=40 radius=1 height=10]\n"
    "       meshtool generate bar OUT [nx=4 ny=4 nz=40 sx=1 sy=1 sz=10]\n"
    "       meshtool generate plane OUT [nx=200 ny=200 size=1 bump=0.05 bumps=3]\n";

// FNV-1a over the raw vertex doubles and face ints: identifies the geometry independently of the file format.
std::uint64_t checksum(const Mesh& m) {
  std::uint64_t h = 1469598103934665603ull;
  auto feed = [&](const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  };
  feed(m.V.data(), m.V.size() * sizeof(double));
  feed(m.F.data(), m.F.size() * sizeof(int));
  return h;
}

int to_int(const std::string& s, const std::string& what) {
  std::size_t pos = 0;
  int v = 0;
  try {
    v = std::stoi(s, &pos);
  } catch (const std::exception&) {
    pos = 0;
  }
  if (pos != s.size() || s.empty()) throw InputError(fmt::format("{}: '{}' is not an integer", what, s));
  return v;
}

double to_double(const std::string& s, const std::string& what) {
  std::size_t pos = 0;
  double v = 0;
  try {
    v = std::stod(s, &pos);
  } catch (const std::exception&) {
    pos = 0;
  }
  if (pos != s.size() || s.empty()) throw InputError(fmt::format("{}: '{}' is not a number", what, s));
  return v;
}

int generate(int argc, char** argv) {
  if (argc < 4) throw InputError(std::string("generate: missing arguments\n") + kUsage);
  const std::string kind = argv[2], out = argv[3];
  std::map<std::string, std::string> kv;
  for (int i = 4; i < argc; ++i) {
    const char* eq = std::strchr(argv[i], '=');
    if (!eq) throw InputError(fmt::format("generate: expected key=value, got '{}'", argv[i]));
    kv[std::string(argv[i], static_cast<std::size_t>(eq - argv[i]))] = eq + 1;
  }
  auto take = [&](const std::string& key, const std::string& def) {
    auto it = kv.find(key);
    if (it == kv.end()) return def;
    const std::string v = it->second;
    kv.erase(it);
    return v;
  };
  Mesh m;
  if (kind == "cylinder") {
    m = make_cylinder(to_int(take("rings", "41"), "rings"), to_int(take("segments", "40"), "segments"),
                      to_double(take("radius", "1"), "radius"), to_double(take("height", "10"), "height"));
  } else if (kind == "bar") {
    m = make_bar(to_int(take("nx", "4"), "nx"), to_int(take("ny", "4"), "ny"), to_int(take("nz", "40"), "nz"),
                 to_double(take("sx", "1"), "sx"), to_double(take("sy", "1"), "sy"), to_double(take("sz", "10"), "sz"));
  } else if (kind == "plane") {
    m = make_bumpy_plane(to_int(take("nx", "200"), "nx"), to_int(take("ny", "200"), "ny"),
                         to_double(take("size", "1"), "size"), to_double(take("bump", "0.05"), "bump"),
                         to_int(take("bumps", "3"), "bumps"));
  } else {
    throw InputError(fmt::format("generate: unknown shape '{}'\n{}", kind, kUsage));
  }
  if (!kv.empty()) throw InputError(fmt::format("generate {}: unknown parameter '{}'", kind, kv.begin()->first));
  validate_mesh(m);
  write_mesh(out, m);
  std::cout << fmt::format("wrote {} ({} vertices, {} faces)\n", out, m.num_vertices(), m.num_faces());
  return 0;
}

int run(int argc, char** argv) {
  if (argc < 2 || std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0) {
    std::cout << kUsage;
    return argc < 2 ? 1 : 0;
  }
  const std::string cmd = argv[1];
  if (cmd == "info" && (argc == 3 || (argc == 4 && std::strcmp(argv[3], "--validate") == 0))) {
    const Mesh m = read_mesh(argv[2]);
    if (argc == 4) validate_mesh(m);
    std::cout << fmt::format("name={} vertices={} faces={} checksum={:016x}\n", m.name, m.num_vertices(),
                             m.num_faces(), checksum(m));
    return 0;
  }
  if (cmd == "subdivide" && argc == 5) {
    const Mesh in = read_mesh(argv[2]);
    validate_mesh(in);
    const Mesh out = loop_subdivide(in, to_int(argv[4], "LEVELS"));
    write_mesh(argv[3], out);
    std::cout << fmt::format("wrote {} ({} vertices, {} faces)\n", argv[3], out.num_vertices(), out.num_faces());
    return 0;
  }
  if (cmd == "convert" && argc == 4) {
    write_mesh(argv[3], read_mesh(argv[2]));
    return 0;
  }
  if (cmd == "generate") return generate(argc, argv);
  std::cerr << kUsage;
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "meshtool: " << e.what() << "\n";
    return db::exit_code(e);
  }
}
