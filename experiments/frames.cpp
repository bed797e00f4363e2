// Issue 5 / thesis 4.4: does the LRI frame choice change the result? Deforms the cases of a config
// (data/experiments/frames.toml) with LAP, TF (free and normalized scale), LRI (every frame strategy x
// orthonormalization) and LRI with its handle frames left at rest (uncoordinated control, thesis fig. 3-4),
// measures each result against the rest mesh and, where one exists, the analytic ideal, and writes
//   results/frames.csv                  one tidy row per case x method x strategy x orthonormalization
//   results/frames_settings.csv         the run's settings, for the report
//   results/meshes/frames/CASE__*.ply   rest, ideal, every result (binary PLY), CASE__roles.sel (0 fixed/1/2 handle)
// Every (case, configuration) is a cell (kind "frames") run in a fresh child process: its own peak RSS; the
// differences between configurations (diff_vs_first_*, diff_vs_polar_max) are measured afterwards from the
// positions the cells leave. A cell solves its frame --frame-repeats times: frame_s is the median, with its spread
// (frame_min_s, frame_max_s, frame_reps). results/frames.md is the report step's (experiments/reports/). Options:
// --help. Exits with kCellsFailedExit (harness/driver.h) when a cell failed, after writing every row.
//
// Cases, "NAME: KIND key=value ..." (a case whose input is absent is skipped with a message):
//   bend   mesh=cylinder:RINGS:SEGMENTS:RADIUS:HEIGHT | mesh=half_tube:PATH, z0, z1, degrees: fixed below z0,
//          handle above z1, bent by `degrees` (ideal: ideal_bend, thesis fig. 4-4). half_tube is CGAL's
//          cylinder.off (a half tube around the x axis) turned onto the z axis.
//   twist  mesh=bar:NX:NY:NZ:SX:SY:SZ, z0, z1, turns, chained=yes|no: fixed below z0, handle above z1 turned by
//          `turns` full turns (ideal: ideal_twist). A single handle transform cannot tell k full turns from none,
//          so a chained twist is a chain of --twist-step degree edits, each re-using the previous result as its
//          rest mesh.
//   edit   path=EDIT (a .edit file or a Botsch-Sorkine stem, relative to --data), family=NAME: no ideal.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include <Eigen/SVD>
#include <fmt/format.h>

#include "solvers/base/atomic_file.h"
#include "core/cli.h"
#include "core/csv.h"
#include "solvers/base/error.h"
#include "core/provenance.h"
#include "solvers/base/resources.h"
#include "core/timer.h"
#include "edit/edit_io.h"
#include "edit/transform.h"
#include "harness/driver.h"
#include "harness/positions.h"
#include "harness/runner.h"
#include "harness/subprocess.h"
#include "mesh/mesh_io.h"
#include "mesh/procedural.h"
#include "methods/deformer.h"
#include "methods/lri.h"
#include "methods/quality_metrics.h"

namespace fs = std::filesystem;
using namespace db;
using namespace db::harness;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ------------------------------------------------------------------------------------------------ cases
struct Case {
  std::string name, family, source;
  Mesh mesh;
  Edit edit;                    // roles; edit.transform = the whole edit (single shot)
  std::optional<Points> ideal;  // analytic target, if any
  double angle_deg = 0;         // nominal edit angle, for the tables
  std::vector<Mat4> chain;      // non-empty: apply these one after another, re-resting after each
};

// "NAME: KIND key=value ..." of a config.
struct CaseDef {
  std::string text, name, kind;
  std::map<std::string, std::string> keys;
  std::string get(const std::string& k) const {
    auto it = keys.find(k);
    if (it == keys.end()) throw UsageError(fmt::format("case '{}': missing {}=", text, k));
    return it->second;
  }
  double number(const std::string& k) const {
    const std::string v = get(k);
    char* end = nullptr;
    const double d = std::strtod(v.c_str(), &end);
    if (v.empty() || end != v.c_str() + v.size() || !std::isfinite(d))
      throw UsageError(fmt::format("case '{}': {}={} is not a number", text, k, v));
    return d;
  }
};

CaseDef parse_case(const std::string& text) {
  CaseDef d;
  d.text = text;
  const std::size_t colon = text.find(':');
  if (colon == std::string::npos || colon == 0) throw UsageError(fmt::format("case '{}': expected NAME: KIND ...", text));
  d.name = text.substr(0, colon);
  std::istringstream in(text.substr(colon + 1));
  in >> d.kind;
  if (d.kind != "bend" && d.kind != "twist" && d.kind != "edit")
    throw UsageError(fmt::format("case '{}': kind '{}' is not bend, twist or edit", text, d.kind));
  for (std::string kv; in >> kv;) {
    const std::size_t eq = kv.find('=');
    if (eq == std::string::npos) throw UsageError(fmt::format("case '{}': '{}' is not key=value", text, kv));
    d.keys[kv.substr(0, eq)] = kv.substr(eq + 1);
  }
  return d;
}

// "cylinder:30:16:1:10" -> {"cylinder", 30, 16, 1, 10}.
std::pair<std::string, std::vector<double>> shape_args(const CaseDef& d) {
  std::string mesh = d.get("mesh");
  std::vector<double> args;
  std::size_t colon = mesh.find(':');
  const std::string shape = mesh.substr(0, colon);
  if (shape == "half_tube") return {shape, {}};
  while (colon != std::string::npos) {
    const std::size_t next = mesh.find(':', colon + 1);
    args.push_back(std::strtod(mesh.substr(colon + 1, next - colon - 1).c_str(), nullptr));
    colon = next;
  }
  return {shape, args};
}

Points transformed(const Points& V, const Mat4& T) {
  Points out(V.rows(), 3);
  for (Eigen::Index i = 0; i < V.rows(); ++i) out.row(i) = apply(T, V.row(i).transpose()).transpose();
  return out;
}

// Fixed below z0, handle above z1 (z along the tube axis); the rest free.
Edit axial_edit(const Mesh& m, double z0, double z1, const std::string& name) {
  Edit e;
  e.name = name;
  e.roles.assign(m.num_vertices(), Role::Free);
  for (int v = 0; v < m.num_vertices(); ++v) {
    if (m.V(v, 2) <= z0 + 1e-9) e.roles[v] = Role::Fixed;
    if (m.V(v, 2) >= z1 - 1e-9) e.roles[v] = Role::Handle;
  }
  return e;
}

// CGAL's cylinder.off is a half tube of radius 1 around the x axis, x in [0, 3], z >= 0. Mapped by the proper
// rotation (x, y, z) -> (-y, -z, x): axis along +z, the material at y <= 0, so a bend towards +y (ideal_bend)
// keeps every fibre at R - y >= R > 0 (bending the other way would fold the 180-degree case through itself).
Mesh canonical_half_tube(const Mesh& raw) {
  Mesh m = raw;
  for (int v = 0; v < m.num_vertices(); ++v) m.V.row(v) << -raw.V(v, 1), -raw.V(v, 2), raw.V(v, 0);
  for (int v = 0; v < m.num_vertices(); ++v) {
    const double r = std::hypot(m.V(v, 0), m.V(v, 1));
    if (std::abs(r - 1) > 1e-3 || m.V(v, 1) > 1e-6 || m.V(v, 2) < -1e-6)
      throw InputError(fmt::format("vertex {} is not on the unit half tube around the x axis this case assumes", v));
  }
  return m;
}

// A bend case: fixed z <= z0, handle z >= z1, ideal_bend between; the handle transform is checked against the ideal.
Case bend_case(const CaseDef& d, const fs::path& data) {
  Case c;
  c.name = d.name;
  c.family = "cylinder_bend";
  const auto [shape, a] = shape_args(d);
  if (shape == "cylinder" && a.size() == 4) {
    c.mesh = make_cylinder(int(a[0]), int(a[1]), a[2], a[3]);
    c.source = "make_cylinder";
  } else if (shape == "half_tube") {
    const fs::path p = data / d.get("mesh").substr(10);
    c.mesh = canonical_half_tube(read_mesh(p.string()));
    c.source = p.string();
  } else {
    throw UsageError(fmt::format("case '{}': mesh is cylinder:RINGS:SEGMENTS:RADIUS:HEIGHT or half_tube:PATH", d.text));
  }
  c.edit = axial_edit(c.mesh, d.number("z0"), d.number("z1"), c.name);
  // Bend exactly between the last fixed and the first handle vertex so that both constraints match the ideal.
  double zf = -1e300, zh = 1e300;
  for (int v = 0; v < c.mesh.num_vertices(); ++v) {
    if (c.edit.roles[v] == Role::Fixed) zf = std::max(zf, c.mesh.V(v, 2));
    if (c.edit.roles[v] == Role::Handle) zh = std::min(zh, c.mesh.V(v, 2));
  }
  c.angle_deg = d.number("degrees");
  c.edit.transform = bend_transform(c.angle_deg * kPi / 180, zf, zh);
  c.ideal = ideal_bend(c.mesh.V, c.angle_deg * kPi / 180, zf, zh);
  const Points h = transformed(c.mesh.V, c.edit.transform);
  for (int v = 0; v < c.mesh.num_vertices(); ++v)
    if (c.edit.roles[v] == Role::Handle && (h.row(v) - c.ideal->row(v)).norm() > 1e-9 * bbox_diagonal(c.mesh.V))
      throw Error("bend case: the handle transform does not match ideal_bend (convention changed?)");
  return c;
}

// A twist of `turns` full turns about the bar axis: fixed bottom, handle top.
Case twist_case(const CaseDef& d, double step_deg) {
  const auto [shape, a] = shape_args(d);
  if (shape != "bar" || a.size() != 6)
    throw UsageError(fmt::format("case '{}': mesh is bar:NX:NY:NZ:SX:SY:SZ", d.text));
  Case c;
  c.name = d.name;
  c.family = "bar_twist";
  c.source = "make_bar";
  c.mesh = make_bar(int(a[0]), int(a[1]), int(a[2]), a[3], a[4], a[5]);
  const double z0 = d.number("z0"), z1 = d.number("z1");
  c.angle_deg = 360.0 * d.number("turns");
  c.edit = axial_edit(c.mesh, z0, z1, c.name);
  c.edit.transform = twist_transform(c.angle_deg * kPi / 180);
  c.ideal = ideal_twist(c.mesh.V, c.angle_deg * kPi / 180, z0, z1);
  if (d.get("chained") == "yes") {
    const int steps = static_cast<int>(std::ceil(c.angle_deg / step_deg - 1e-9));
    for (int s = 0; s < steps; ++s) c.chain.push_back(twist_transform(c.angle_deg / steps * kPi / 180));
  } else if (d.get("chained") != "no") {
    throw UsageError(fmt::format("case '{}': chained is yes or no", d.text));
  }
  return c;
}

Case edit_case(const CaseDef& d, const fs::path& data) {
  const fs::path p = data / d.get("path");
  EditCase ec = load_edit_case(p.string());
  Case c;
  c.name = d.name;
  c.family = d.get("family");
  c.source = p.string();
  c.mesh = std::move(ec.mesh);
  c.edit = std::move(ec.edit);
  c.angle_deg = std::acos(std::clamp((c.edit.transform.topLeftCorner<3, 3>().trace() - 1) / 2, -1.0, 1.0)) * 180 / kPi;
  return c;
}

//! \throw UsageError for a malformed definition, InputError when its input is absent or unusable.
Case build_case(const CaseDef& d, const fs::path& data, double step_deg) {
  if (d.kind == "bend") return bend_case(d, data);
  if (d.kind == "twist") return twist_case(d, step_deg);
  return edit_case(d, data);
}

// ------------------------------------------------------------------------------------------------ the cell
struct Config {
  std::string method, frames, ortho;
  std::string label() const { return method == "lri" ? fmt::format("lri-{}-{}", frames, ortho) : method; }
};

// One configuration on one case: the deformed positions and what the deformers reported.
struct Run {
  Points V;
  double init_s = 0;
  std::vector<double> frame_s;  // per repetition of the frame: its time (a chain: the sum over its steps)
  double fallbacks = kNaN, sigma_min = kNaN;  // LRI: sigma_min = smallest singular value of a solved frame
  std::size_t n_frames = 0, n_positions = 0, factor_bytes = 0;
};

// After each deform(): times and sizes sum / report over the chain's steps; frame_fallbacks is the last step's,
// sigma_min the minimum over all steps (1 for a rotation; near 0 where least squares averaged opposite rotations).
void note(Run& r, const Deformer& d) {
  r.init_s += d.times().init();
  if (auto* l = dynamic_cast<const LriDeformer*>(&d)) {
    r.fallbacks = l->rest_frames().fallbacks;
    double sm = std::isnan(r.sigma_min) ? 1e300 : r.sigma_min;
    for (const Mat3& F : l->solved_frames_raw()) {
      const Eigen::JacobiSVD<Mat3> svd(F);
      const Vec3 sv = svd.singularValues();
      sm = std::min(sm, sv(2));
    }
    r.sigma_min = sm;
  }
  r.n_frames = d.systems().size() > 1 ? d.systems()[0].n : 0;
  r.n_positions = d.systems().back().n;
  r.factor_bytes = d.factor_bytes();
}

// The frame `repeats` times with the same transform, for its spread (the first result kept); repetition k's time is
// added to r.frame_s[k].
Points repeated_deform(Deformer& d, const Mat4& transform, int repeats, Run& r) {
  r.frame_s.resize(static_cast<std::size_t>(repeats), 0.0);
  Points V;
  for (int k = 0; k < repeats; ++k) {
    Points P = d.deform(transform);
    if (k == 0) V = std::move(P);
    r.frame_s[static_cast<std::size_t>(k)] += d.times().frame();
  }
  return V;
}

// A configuration of the study as deform options (methods/deform_options.h keys).
DeformOptions options_of(const Config& cfg, unsigned seed) {
  std::vector<std::pair<std::string, std::string>> items = {{"method", cfg.method}};
  if (cfg.method == "tf-normalized")  // TF's rotations without its scale (issue 17)
    items = {{"method", "tf"}, {"tf_scale", "normalized"}};
  if (cfg.method == "lri-uncoordinated")  // handle frames left at rest (thesis fig. 3-4)
    items = {{"method", "lri"}, {"lri_frame_control", "uncoordinated"}};
  if (cfg.method == "lri")
    items.insert(items.end(), {{"lri_frames", cfg.frames}, {"lri_orthonormalize", cfg.ortho},
                               {"lri_seed", std::to_string(seed)}});
  DeformOptions o;
  for (const auto& [key, value] : items) set_deform_option(o, key, value);
  return o;
}

Run run_config(const Case& c, const Config& cfg, unsigned seed, int repeats) {
  const DeformOptions o = options_of(cfg, seed);
  Run r;
  if (c.chain.empty()) {
    auto d = make_deformer(c.mesh, c.edit, o);
    r.V = repeated_deform(*d, c.edit.transform, repeats, r);
    note(r, *d);
    return r;
  }
  Mesh cur = c.mesh;
  for (const Mat4& step : c.chain) {
    auto d = make_deformer(cur, c.edit, o);  // rebuilt on the previous result: a new rest pose per step
    cur.V = repeated_deform(*d, step, repeats, r);
    note(r, *d);
  }
  r.V = cur.V;
  return r;
}

// Metrics of one result against the rest mesh and the ideal. Normal-based metrics throw on a result with a
// vanished vertex normal (a collapsed 1-ring): NaN ("n/a") then, with a note.
void add_metrics(CellResult& res, const Case& c, const Points& V) {
  const Adjacency adj = vertex_adjacency(c.mesh);
  std::string notes;
  auto guarded = [&](const char* what, const std::function<void()>& f) {
    try {
      f();
    } catch (const Error& e) {
      notes += fmt::format("{} n/a: {}; ", what, e.what());
    }
  };
  res.set("edge_distortion", edge_length_distortion(c.mesh.V, V, adj));
  res.set("max_displacement", distance_between(V, c.mesh.V, bbox_diagonal(c.mesh.V)).max);
  res.set("arap_energy", arap_energy(c.mesh.V, V, adj));
  guarded("lri_detail_error", [&] { res.set("lri_detail_error", lri_detail_error(c.mesh.V, V, c.mesh.F, adj)); });
  guarded("normal_dev_local",
          [&] { res.set("normal_dev_local_mean_deg", local_normal_deviation(c.mesh.V, V, c.mesh.F, adj).mean_deg); });
  if (is_closed(c.mesh.F))
    if (const auto vol = volume_change(c.mesh.V, V, c.mesh.F)) res.set("volume_change", *vol);
  if (c.ideal) {
    const DistanceStats ds = distance_between(V, *c.ideal, bbox_diagonal(c.mesh.V));
    res.set("ideal_rms", ds.rms);
    res.set("ideal_max", ds.max);
    guarded("normal_dev_ideal", [&] {
      const AngleStats nd = normal_deviation(V, *c.ideal, c.mesh.F);
      res.set("normal_dev_ideal_mean_deg", nd.mean_deg);
      res.set("normal_dev_ideal_max_deg", nd.max_deg);
    });
  }
  if (!notes.empty()) res.set_text("notes", notes);
}

CellResult measure_frames_cell(const CellSpec& s) {
  s.check_keys({"case", "data", "twist_step", "method", "frames", "ortho", "seed", "frame_repeats", "positions",
                "mesh_out"});
  const Case c = build_case(parse_case(s.get("case")), s.get("data"), s.real("twist_step", 30, 1e-3, 180));
  const Config cfg{s.get("method"), s.get("frames", "n/a"), s.get("ortho", "n/a")};
  const Run r = run_config(c, cfg, static_cast<unsigned>(s.integer("seed", 1, 0, 4294967295LL)),
                           static_cast<int>(s.integer("frame_repeats", 1, 1, 100000)));
  CellResult res;
  add_metrics(res, c, r.V);
  res.set("frame_fallbacks", r.fallbacks);
  res.set("frame_sigma_min", r.sigma_min);
  const bool lri = cfg.method == "lri" || cfg.method == "lri-uncoordinated";
  res.set("n_frames_system", lri ? double(r.n_frames) : kNaN);
  res.set("n_positions_system", double(r.n_positions));
  res.set("factor_bytes", double(r.factor_bytes), "bytes");
  res.set("init_s", r.init_s, "s");
  set_spread(res, "frame_s", r.frame_s);  // the median repetition, with frame_min_s, frame_max_s, frame_reps
  res.set("peak_rss_bytes", double(peak_rss_bytes()), "bytes");
  if (s.has("positions")) write_positions(s.get("positions"), r.V);
  if (!s.get("mesh_out", "").empty()) {
    Mesh m = c.mesh;
    m.V = r.V;
    write_mesh(s.get("mesh_out"), m);
  }
  return res;
}

// ------------------------------------------------------------------------------------------------ the driver
struct Options {
  std::string data = "data", out = "results/frames.csv", meshes = "results/meshes/frames";
  bool no_meshes = false, dry_run = false;
  double twist_step = 30, cell_timeout_s = 600;
  int frame_repeats = 5;
  std::string only;
  unsigned seed = 1;
  std::vector<std::string> cases, methods = {"lap", "tf", "tf-normalized", "lri", "lri-uncoordinated"},
                                  lri_frames = enum_names<FrameStrategy>(),
                                  lri_ortho = enum_names<Orthonormalization>();
};

void define_options(CLI::App& app, Options& o) {
  add_config_option(app, "data/experiments/frames.toml");
  app.add_option("--data", o.data, "data directory; case paths are inside it")->capture_default_str();
  app.add_option("--out", o.out, "the CSV")->capture_default_str();
  app.add_option("--meshes", o.meshes, "where the rest, ideal and result meshes go")->capture_default_str();
  app.add_flag("--no-meshes", o.no_meshes, "write no meshes");
  app.add_flag("--dry-run", o.dry_run, "print the grid's cells (one spec a line) and exit");
  app.add_option("--case", o.cases, "a case: \"NAME: bend|twist|edit key=value ...\" (see the source's header)");
  app.add_option("--only", o.only, "run only the cases whose name contains this");
  app.add_option("--methods", o.methods,
                 "methods (tf-normalized: tf --tf-scale normalized; lri-uncoordinated: lri with first-neighbour "
                 "frames, Gram-Schmidt and --lri-frame-control uncoordinated)")
      ->delimiter(',')
      ->check(cli::OneOf({"lap", "tf", "tf-normalized", "lri", "lri-uncoordinated"}))
      ->capture_default_str();
  app.add_option("--lri-frames", o.lri_frames, "LRI frame strategies")->delimiter(',')
      ->check(cli::OneOf(enum_names<FrameStrategy>()))->capture_default_str();
  app.add_option("--lri-orthonormalize", o.lri_ortho, "LRI orthonormalizations")->delimiter(',')
      ->check(cli::OneOf(enum_names<Orthonormalization>()))->capture_default_str();
  app.add_option("--twist-step", o.twist_step, "degrees per edit of a chained twist")->check(cli::Real(1e-3, 180))
      ->capture_default_str();
  app.add_option("--seed", o.seed, "seed of the random frame strategy")->transform(cli::Integer(0, 4294967295LL))
      ->capture_default_str();
  app.add_option("--cell-timeout-s", o.cell_timeout_s, "kill a cell after this")->check(cli::Real(1, 1e7))
      ->capture_default_str();
  app.add_option("--frame-repeats", o.frame_repeats, "times each frame is solved, for its median and spread")
      ->transform(cli::Integer(1, 100000))->capture_default_str();
}

std::vector<Config> configs_of(const Options& o) {
  std::vector<Config> v;
  for (const auto& m : o.methods)
    if (m != "lri") v.push_back({m, "n/a", "n/a"});
  if (std::find(o.methods.begin(), o.methods.end(), "lri") != o.methods.end())
    for (const auto& orth : o.lri_ortho)
      for (const auto& f : o.lri_frames) v.push_back({"lri", f, orth});
  return v;
}

void write_case_meshes(const Case& c, const std::string& dir) {
  const fs::path stem = fs::path(dir) / c.name;
  write_mesh(stem.string() + "__rest.ply", c.mesh);
  if (c.ideal) {
    Mesh im = c.mesh;
    im.V = *c.ideal;
    write_mesh(stem.string() + "__ideal.ply", im);
  }
  write_atomically(stem.string() + "__roles.sel", [&](std::ostream& os) {
    os << "# " << c.name << ": per vertex status 0 fixed, 1 free, 2 handle\n";
    for (Role r : c.edit.roles) os << static_cast<int>(r) << "\n";
  });
}

// One configuration of a case as it came back from its cell.
struct Outcome {
  Config config;
  CellResult res;
  std::string positions;
};

// The cell of one configuration on one case.
CellSpec spec_for(const Options& o, const CaseDef& d, const Config& cfg, const std::string& positions) {
  CellSpec s("frames");
  s.set("case", d.text).set("data", o.data).set("twist_step", o.twist_step).set("method", cfg.method);
  if (cfg.method == "lri") s.set("frames", cfg.frames).set("ortho", cfg.ortho);
  s.set("seed", static_cast<double>(o.seed)).set("frame_repeats", o.frame_repeats);
  if (!positions.empty()) s.set("positions", positions);
  if (!o.no_meshes) s.set("mesh_out", (fs::path(o.meshes) / (d.name + "__" + cfg.label() + ".ply")).string());
  return s;
}

std::vector<Outcome> run_case(const Options& o, const CaseDef& d, const Case& c, const fs::path& scratch,
                              FailedCells& failed) {
  std::vector<Outcome> out;
  RunOptions ro;
  ro.timeout_s = o.cell_timeout_s;
  for (const Config& cfg : configs_of(o)) {
    Outcome x{cfg, {}, (scratch / (c.name + "__" + cfg.label() + ".pos")).string()};
    const CellSpec spec = spec_for(o, d, cfg, x.positions);
    x.res = run_cell(self_executable(), spec, ro);
    failed.note(spec.text(), x.res);
    if (!x.res.ok()) std::cerr << fmt::format("[frames] {} {}: {} ({})\n", c.name, cfg.label(), x.res.message, x.res.exit);
    else if (!x.res.text("notes").empty())
      std::cerr << fmt::format("[frames] {} {}: {}\n", c.name, cfg.label(), x.res.text("notes"));
    out.push_back(std::move(x));
  }
  return out;
}

// diff_vs_first_* (against the first-neighbour frames, same orthonormalization) and diff_vs_polar_max (against
// polar, same strategy) of every LRI result, from the positions the cells left.
void add_differences(std::vector<Outcome>& runs, const Case& c) {
  const double diag = bbox_diagonal(c.mesh.V);
  std::map<std::string, Points> V;
  for (const Outcome& x : runs)
    if (x.res.ok() && fs::exists(x.positions)) V[x.config.label()] = read_positions(x.positions);
  for (Outcome& x : runs) {
    if (x.config.method != "lri" || !V.count(x.config.label())) continue;
    const Points& P = V.at(x.config.label());
    if (auto f = V.find(Config{"lri", "first", x.config.ortho}.label()); f != V.end()) {
      const DistanceStats df = distance_between(P, f->second, diag);
      x.res.set("diff_vs_first_max", df.max);
      x.res.set("diff_vs_first_rms", df.rms);
    }
    if (auto p = V.find(Config{"lri", x.config.frames, "polar"}.label()); p != V.end())
      x.res.set("diff_vs_polar_max", distance_between(P, p->second, diag).max);
  }
  for (const Outcome& x : runs) fs::remove(x.positions);
}

std::string opt_num(double v) { return std::isnan(v) ? "n/a" : num(v); }

void add_rows(CsvTable& csv, const Case& c, const std::vector<Outcome>& runs) {
  for (const Outcome& x : runs) {
    const CellResult& r = x.res;
    CsvTable::Row row = {{"case", c.name},
                         {"family", c.family},
                         {"source", c.source},
                         {"mesh", c.mesh.name},
                         {"vertices", std::to_string(c.mesh.num_vertices())},
                         {"faces", std::to_string(c.mesh.num_faces())},
                         {"closed", is_closed(c.mesh.F) ? "yes" : "no"},
                         {"handle", std::to_string(c.edit.count(Role::Handle))},
                         {"fixed", std::to_string(c.edit.count(Role::Fixed))},
                         {"free", std::to_string(c.edit.count(Role::Free))},
                         {"angle_deg", num(c.angle_deg)},
                         {"protocol", c.chain.empty() ? "single" : "chained"},
                         {"steps", std::to_string(c.chain.empty() ? 1 : c.chain.size())},
                         {"method", x.config.method},
                         {"frames", x.config.frames},
                         {"orthonormalize", x.config.ortho},
                         {"config", x.config.label()},
                         {"status", r.ok() ? "ok" : fmt::format("error ({}): {}", r.exit, r.message)}};
    for (const char* m : {"ideal_rms", "ideal_max", "edge_distortion", "max_displacement", "arap_energy",
                          "lri_detail_error", "normal_dev_ideal_mean_deg", "normal_dev_ideal_max_deg", "normal_dev_local_mean_deg",
                          "volume_change", "diff_vs_first_max", "diff_vs_first_rms", "diff_vs_polar_max",
                          "frame_fallbacks", "frame_sigma_min", "n_frames_system", "n_positions_system",
                          "factor_bytes", "init_s", "frame_s", "peak_rss_bytes"}) {
      row.emplace_back(m, opt_num(r.get(m)));
      if (std::string(m) == "init_s" || std::string(m) == "frame_s") add_spread_columns(row, r, m);
    }
    csv.add(std::move(row));
  }
}

void log_case(const Case& c, const std::vector<Outcome>& runs, double seconds) {
  auto rms = [&](const std::string& label) {
    for (const Outcome& x : runs)
      if (x.config.label() == label && !std::isnan(x.res.get("ideal_rms"))) return fmt::format("{:.4f}", x.res.get("ideal_rms"));
    return std::string("  n/a ");
  };
  double polar = 0, gs = 0;
  for (const Outcome& x : runs) {
    const double d = x.res.get("diff_vs_first_max");
    double& m = x.config.ortho == "polar" ? polar : gs;
    if (!std::isnan(d)) m = std::max(m, d);
  }
  std::cerr << fmt::format("[frames] {:22s} {:5d} v  {:6.2f} s | ideal rms lap {} tf {} lri-first-gs {} lri-height-gs {} | "
                           "strategy diff polar {:.1e} gs {:.1e}\n",
                           c.name, c.mesh.num_vertices(), seconds, rms("lap"), rms("tf"), rms("lri-first-gram_schmidt"),
                           rms("lri-height_angle-gram_schmidt"), polar, gs);
}

int run(Options& o) {
  cli::check_output("--out", o.out, {".csv"});
  if (!o.no_meshes) check_output_dir("--meshes", o.meshes);
  std::vector<CaseDef> defs;
  for (const auto& text : o.cases)
    if (CaseDef d = parse_case(text); o.only.empty() || d.name.find(o.only) != std::string::npos) defs.push_back(d);
  if (defs.empty()) throw UsageError("no case selected (--case, --only, or a --config that lists cases)");
  if (o.dry_run) {  // the grid, a plain list: cases x configurations
    for (const CaseDef& d : defs)
      for (const Config& cfg : configs_of(o)) std::cout << spec_for(o, d, cfg, "").text() << "\n";
    return 0;
  }
  if (!o.no_meshes) fs::create_directories(o.meshes);
  const fs::path scratch = fs::path(o.out).parent_path() / "cells" / "frames";
  fs::create_directories(scratch);
  std::cerr << "[frames] " << provenance_summary() << "\n";
  CsvTable csv;
  Timer total;
  int cases = 0;
  FailedCells failed("frames");
  for (const CaseDef& d : defs) {
    Timer tc;
    std::optional<Case> c;
    try {
      c = build_case(d, o.data, o.twist_step);
    } catch (const InputError& e) {
      std::cerr << "[frames] skipping " << d.name << ": " << e.what() << "\n";
      continue;
    }
    if (!o.no_meshes) write_case_meshes(*c, o.meshes);
    std::vector<Outcome> runs = run_case(o, d, *c, scratch, failed);
    add_differences(runs, *c);
    add_rows(csv, *c, runs);
    log_case(*c, runs, tc.seconds());
    ++cases;
  }
  if (csv.empty()) throw InputError("no case could be run (see the skipped cases above)");
  csv.write(o.out);
  write_settings((fs::path(o.out).parent_path() / "frames_settings.csv").string(),
                 {{"cases", std::to_string(cases)}, {"rows", std::to_string(csv.size())},
                  {"seconds", fmt::format("{:.0f}", total.seconds())}, {"twist_step_deg", num(o.twist_step)},
                  {"seed", std::to_string(o.seed)}, {"frame_repeats", std::to_string(o.frame_repeats)},
                  {"csv", fs::path(o.out).filename().string()}});
  std::cerr << fmt::format("[frames] wrote {} ({} rows) in {:.1f} s\n", o.out, csv.size(), total.seconds());
  return failed.exit_code();
}

}  // namespace

int main(int argc, char** argv) {
  if (is_cell_invocation(argc, argv)) return cell_main(argc, argv, {{"frames", measure_frames_cell}});
  CLI::App app("Does the LRI frame choice change the result? LAP, TF and LRI (frame strategy x orthonormalization) on "
               "the cases of a config, each (case, configuration) in a fresh child process.",
               "exp_frames");
  Options o;
  define_options(app, o);
  return cli::run(app, argc, argv, [&] { return run(o); });
}
