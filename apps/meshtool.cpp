// meshtool: mesh utilities for the data step (scripts/data.sh), for inspecting inputs and for preparing
// real-world meshes (`meshtool --help`; docs/cli.md "meshtool").
//   meshtool info FILE [--validate]          name, #V, #F, a content checksum and the topology
//   meshtool convert IN OUT [--stl binary]   re-write in the format given by OUT's extension
//   meshtool repair IN OUT [--max-list N]    split non-manifold vertices and edges, drop degenerate and duplicate
//                                            faces, remove isolated vertices; reports each change
//   meshtool subdivide IN OUT LEVELS         Loop subdivision (OpenMesh)
//   meshtool generate cylinder|bar|plane OUT [key=value ...]
// subdivide and generate predict the vertices, faces and peak memory of their result first and refuse above
// --memory-budget-mb (default half the RAM) before allocating anything. Exit codes: 0 ok, 1 usage, 2 bad input,
// 4 over the memory budget.
#include <algorithm>
#include <cstdint>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/cli.h"
#include "solvers/base/error.h"
#include "solvers/base/resources.h"
#include "mesh/mesh.h"
#include "mesh/mesh_io.h"
#include "mesh/procedural.h"
#include "mesh/repair.h"
#include "mesh/subdivision.h"

namespace {

using namespace db;

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

// ---------------------------------------------------------------- predictions
// What a result will take, worked out from counts alone before anything is allocated.
struct Prediction {
  double vertices = 0, faces = 0, bytes = 0;
};

// The result mesh (24 bytes a vertex, 12 a face) and validate_mesh's incidence lists (8 a vertex, 12 a face).
double mesh_and_validation_bytes(double v, double f) { return 32 * v + 24 * f; }

// The process itself: code, libraries, I/O buffers.
constexpr double kProcessBytes = 16.0 * 1024 * 1024;

void check_budget(const Prediction& p, std::size_t budget, const std::string& what) {
  const double mb = 1024.0 * 1024.0;
  if (p.vertices > kMaxElements || p.faces > kMaxElements)
    throw BudgetError(fmt::format("{} would have {:.4g} vertices and {:.4g} faces: more than the {} a mesh may hold "
                                  "(32-bit indices); refused before allocating",
                                  what, p.vertices, p.faces, kMaxElements));
  if (p.bytes > static_cast<double>(budget))
    throw BudgetError(fmt::format("{} would have {:.4g} vertices and {:.4g} faces and need ~{:.0f} MB at its peak, "
                                  "over the memory budget of {:.0f} MB (--memory-budget-mb); refused before allocating",
                                  what, p.vertices, p.faces, p.bytes / mb, static_cast<double>(budget) / mb));
}

// Loop subdivision splits every edge and every face into four: V' = V + E, E' = 2E + 3F, F' = 4F. OpenMesh holds
// per vertex a halfedge handle, the point and the subdivider's new position (52 bytes at most), per edge two
// halfedges and the edge point (56), per face a handle (4); the result is then copied out and validated.
Prediction predict_subdivision(const Mesh& in, int levels) {
  double v = in.num_vertices(), f = in.num_faces();
  double e = static_cast<double>(vertex_adjacency(in).nbr.size()) / 2;
  for (int l = 0; l < levels; ++l) {
    const double v1 = v + e, e1 = 2 * e + 3 * f, f1 = 4 * f;
    v = v1, e = e1, f = f1;
  }
  return {v, f,
          kProcessBytes + 52 * v + 56 * e + 4 * f + mesh_and_validation_bytes(v, f) +
              mesh_and_validation_bytes(in.num_vertices(), in.num_faces())};
}

// ---------------------------------------------------------------- generate: shapes and their parameters
struct Param {
  std::string key, default_value;
  CLI::Validator check;
  bool integer;
};

const std::map<std::string, std::vector<Param>>& shapes() {
  const double big = 1e300, tiny = 1e-300;
  const long long most = 1 << 30;  // the counts are ints; larger ones are refused by the prediction anyway
  static const std::map<std::string, std::vector<Param>> s = {
      {"cylinder",
       {{"rings", "41", cli::Integer(2, most), true},
        {"segments", "40", cli::Integer(3, most), true},
        {"radius", "1", cli::Real(tiny, big), false},
        {"height", "10", cli::Real(tiny, big), false}}},
      {"bar",
       {{"nx", "4", cli::Integer(1, most), true},
        {"ny", "4", cli::Integer(1, most), true},
        {"nz", "40", cli::Integer(1, most), true},
        {"sx", "1", cli::Real(tiny, big), false},
        {"sy", "1", cli::Real(tiny, big), false},
        {"sz", "10", cli::Real(tiny, big), false}}},
      {"plane",
       {{"nx", "200", cli::Integer(1, most), true},
        {"ny", "200", cli::Integer(1, most), true},
        {"size", "1", cli::Real(tiny, big), false},
        {"bump", "0.05", cli::Real(-big, big), false},
        {"bumps", "3", cli::Integer(0, most), true}}},
  };
  return s;
}

std::string shape_help() {
  std::string h;
  for (const auto& [name, params] : shapes()) {
    h += fmt::format("\n  {}:", name);
    for (const Param& p : params) h += fmt::format(" {}={}", p.key, p.default_value);
  }
  return h;
}

// key=value arguments over the shape's defaults, each value checked by its parameter's validator.
std::map<std::string, double> shape_values(const std::string& shape, const std::vector<std::string>& args) {
  const auto& params = shapes().at(shape);
  std::map<std::string, std::string> given;
  for (const std::string& a : args) {
    const auto eq = a.find('=');
    if (eq == std::string::npos) throw UsageError(fmt::format("generate {}: expected key=value, got '{}'", shape, a));
    const std::string key = a.substr(0, eq);
    if (std::none_of(params.begin(), params.end(), [&](const Param& p) { return p.key == key; }))
      throw UsageError(fmt::format("generate {}: unknown parameter '{}' (parameters:{})", shape, key, shape_help()));
    if (!given.emplace(key, a.substr(eq + 1)).second)
      throw UsageError(fmt::format("generate {}: parameter '{}' given twice", shape, key));
  }
  std::map<std::string, double> values;
  for (const Param& p : params) {
    std::string v = given.count(p.key) ? given[p.key] : p.default_value;
    const std::string err = p.check(v);
    if (!err.empty()) throw UsageError(fmt::format("generate {}: {}: {}", shape, p.key, err));
    values[p.key] = p.integer ? static_cast<double>(std::stoll(v)) : std::stod(v);
  }
  return values;
}

Prediction predict_shape(const std::string& shape, std::map<std::string, double> k) {
  Prediction p;
  if (shape == "cylinder") {
    p.vertices = k["rings"] * k["segments"];
    p.faces = 2 * (k["rings"] - 1) * k["segments"];
  } else if (shape == "plane") {
    p.vertices = (k["nx"] + 1) * (k["ny"] + 1);
    p.faces = 2 * k["nx"] * k["ny"];
  } else {
    const double nx = k["nx"], ny = k["ny"], nz = k["nz"];
    p.vertices = (nx + 1) * (ny + 1) * (nz + 1) - (nx - 1) * (ny - 1) * (nz - 1);
    p.faces = 4 * (nx * ny + ny * nz + nz * nx);
    // make_bar numbers the whole (nx+1)(ny+1)(nz+1) lattice (4 bytes a point) and grows its coordinates.
    p.bytes = 4 * (nx + 1) * (ny + 1) * (nz + 1) + 2 * 24 * p.vertices;
  }
  p.bytes += kProcessBytes + mesh_and_validation_bytes(p.vertices, p.faces);
  return p;
}

Mesh make_shape(const std::string& shape, std::map<std::string, double> k) {
  auto i = [&](const char* key) { return static_cast<int>(k[key]); };
  if (shape == "cylinder") return make_cylinder(i("rings"), i("segments"), k["radius"], k["height"]);
  if (shape == "bar") return make_bar(i("nx"), i("ny"), i("nz"), k["sx"], k["sy"], k["sz"]);
  return make_bumpy_plane(i("nx"), i("ny"), k["size"], k["bump"], i("bumps"));
}

// ---------------------------------------------------------------- subcommands
std::string mb(double bytes) { return fmt::format("{:.1f} MB", bytes / (1024.0 * 1024.0)); }

void report_written(const std::string& out, const Mesh& m, const Prediction* p = nullptr) {
  std::cout << fmt::format("wrote {} ({} vertices, {} faces)", out, m.num_vertices(), m.num_faces());
  if (p) std::cout << fmt::format("; peak memory predicted {}, peak RSS {}", mb(p->bytes), mb(peak_rss_bytes()));
  std::cout << "\n";
}

int info(const std::string& file, bool validate) {
  const Mesh m = read_mesh(file);
  if (validate) validate_mesh(m);
  std::cout << fmt::format("name={} vertices={} faces={} checksum={:016x}\n", m.name, m.num_vertices(),
                           m.num_faces(), checksum(m));
  std::cout << "topology: " << find_non_manifold(m).summary() << "\n";
  return 0;
}

int repair(const std::string& in, const std::string& out, std::size_t max_list) {
  cli::check_output("OUT", out, mesh_extensions(), {in});
  const Mesh m = read_mesh(in);
  RepairReport report;
  const Mesh fixed = repair_mesh(m, report);
  std::cout << fmt::format("{}: {}\n", in, report.summary());
  for (const std::string& line : report.details(max_list)) std::cout << "  " << line << "\n";
  std::cout << fmt::format("components: {} before, {} after{}\n", report.components_before, report.components_after,
                           report.detached.empty() ? "" : fmt::format(" (detached pieces: {})", report.detached.size()));
  write_mesh(out, fixed);
  report_written(out, fixed);
  return 0;
}

int subdivide(const std::string& in, const std::string& out, int levels, std::size_t budget) {
  cli::check_output("OUT", out, mesh_extensions(), {in});
  const Mesh m = read_mesh(in);
  validate_mesh(m);  // OpenMesh needs an oriented 2-manifold
  const Prediction p = predict_subdivision(m, levels);
  check_budget(p, budget, fmt::format("{} subdivided {} times", in, levels));
  const Mesh s = loop_subdivide(m, levels);
  write_mesh(out, s);
  report_written(out, s, &p);
  return 0;
}

int generate(const std::string& shape, const std::string& out, const std::vector<std::string>& args,
             std::size_t budget) {
  cli::check_output("OUT", out, mesh_extensions());
  const auto values = shape_values(shape, args);
  const Prediction p = predict_shape(shape, values);
  check_budget(p, budget, fmt::format("the generated {}", shape));
  const Mesh m = make_shape(shape, values);
  validate_mesh(m);
  write_mesh(out, m);
  report_written(out, m, &p);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Mesh utilities: inspect, convert, repair, subdivide and generate triangle meshes (.off, .ply, .obj, "
               ".stl).\n"
               "Exit codes: 0 ok, 1 usage, 2 bad input, 4 over the memory budget.",
               "meshtool"};
  app.require_subcommand(0, 1);  // none given: checked below, so that a misspelled one is named
  std::string in, out, shape, stl = "ascii";
  bool validate = false;
  int levels = 0;
  long long budget_mb = static_cast<long long>(physical_memory_bytes() / 2 / (1024 * 1024));
  std::size_t max_list = 20;
  std::vector<std::string> params;
  auto budget_option = [&](CLI::App* sub) {
    sub->add_option("--memory-budget-mb", budget_mb, "refuse a result predicted to need more (default: half the RAM)")
        ->transform(cli::Integer(1, 1ll << 40))
        ->capture_default_str();
  };

  CLI::App* info_cmd =
      app.add_subcommand("info", "print name, #vertices, #faces, a geometry checksum and the topology");
  info_cmd->add_option("FILE", in, "mesh file")->required();
  info_cmd->add_flag("--validate", validate, "also check what the deformers need (exit 2 naming the first problem)");

  CLI::App* convert_cmd = app.add_subcommand("convert", "re-write IN in the format of OUT's extension");
  convert_cmd->add_option("IN", in, "input mesh")->required();
  convert_cmd->add_option("OUT", out, "output mesh (.off, .ply binary, .obj, .stl)")->required();
  convert_cmd
      ->add_option("--stl", stl, "an .stl OUT as ascii (exact doubles) or binary (coordinates rounded to floats)")
      ->check(cli::OneOf({"ascii", "binary"}))
      ->capture_default_str();

  CLI::App* repair_cmd = app.add_subcommand(
      "repair",
      "make a mesh manifold for cotan weights and LRI: drop degenerate and duplicate faces, split non-manifold "
      "vertices and edges, remove isolated vertices; prints each change");
  repair_cmd->add_option("IN", in, "input mesh")->required();
  repair_cmd->add_option("OUT", out, "output mesh (.off, .ply, .obj, .stl)")->required();
  repair_cmd->add_option("--max-list", max_list, "changes listed per kind (0: all)")
      ->transform(cli::Integer(0, 1ll << 40))
      ->capture_default_str();

  CLI::App* subdivide_cmd = app.add_subcommand("subdivide", "Loop subdivision (OpenMesh)");
  subdivide_cmd->add_option("IN", in, "input mesh (a manifold)")->required();
  subdivide_cmd->add_option("OUT", out, "output mesh")->required();
  subdivide_cmd->add_option("LEVELS", levels, "subdivision levels")->required()->transform(cli::Integer(0, 30));
  budget_option(subdivide_cmd);

  CLI::App* generate_cmd =
      app.add_subcommand("generate", "procedural test shapes; parameters and defaults:" + shape_help());
  generate_cmd->add_option("SHAPE", shape, "cylinder, bar or plane")
      ->required()
      ->check(cli::OneOf({"cylinder", "bar", "plane"}));
  generate_cmd->add_option("OUT", out, "output mesh")->required();
  generate_cmd->add_option("PARAMS", params, "key=value (see above)");
  budget_option(generate_cmd);

  return cli::run(app, argc, argv, [&] {
    const std::size_t budget = static_cast<std::size_t>(budget_mb) * 1024 * 1024;
    if (info_cmd->parsed()) return info(in, validate);
    if (repair_cmd->parsed()) return repair(in, out, max_list);
    if (subdivide_cmd->parsed()) return subdivide(in, out, levels, budget);
    if (generate_cmd->parsed()) return generate(shape, out, params, budget);
    if (!convert_cmd->parsed())
      throw UsageError("a subcommand is required: info, convert, repair, subdivide or generate");
    cli::check_output("OUT", out, mesh_extensions(), {in});
    if (convert_cmd->count("--stl") > 0 && mesh_extension(out) != ".stl")
      throw UsageError(fmt::format("--stl: OUT {} is not an .stl file", out));
    write_mesh(out, read_mesh(in), {stl == "binary" ? StlEncoding::Binary : StlEncoding::Ascii});
    return 0;
  });
}
