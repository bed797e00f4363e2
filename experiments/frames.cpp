// Issue 5 / thesis 4.4: does the LRI frame choice change the result? Deforms a set of cases with LAP, TF and LRI
// (every frame strategy x orthonormalization), measures each result against the rest mesh and, where one exists,
// the analytic ideal, and writes
//   results/frames.csv                  one tidy row per case x method x strategy x orthonormalization
//   results/meshes/frames/CASE__*.ply   rest, ideal, every result (binary PLY), CASE__roles.sel (0 fixed/1/2 handle)
//   results/frames.md                   the verdict, quoting the measured numbers
// Cases (each skipped with a message when its input is absent):
//  - procedural cylinders (make_cylinder) bent by 90 and 180 degrees, ideal = ideal_bend (thesis fig. 4-4);
//  - the CGAL cylinder data/meshes/cylinder.off (a half tube) bent the same way, in canonical coordinates;
//  - a bar (make_bar) twisted by 1, 2 and 3 full turns, ideal = ideal_twist. A single handle transform cannot
//    tell k full turns from none (the rotation matrix is the identity), so twists are applied as a chain of
//    --twist-step degree edits, each re-using the previous result as its rest mesh; one single-shot 1-turn case
//    shows what a single transform gives;
//  - the CGAL dino's head turned 90 degrees (data/edits/dino_head.edit), no ideal;
//  - the four Botsch-Sorkine 2008 edits (data/bs08), no ideal.
//
//   exp_frames [--data DIR] [--shared DIR] [--out results/frames.csv] [--md results/frames.md]
//              [--meshes DIR | --no-meshes] [--twist-step DEG] [--only SUBSTRING] [--seed N]
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include <Eigen/SVD>
#include <fmt/format.h>

#include "core/args.h"
#include "core/atomic_file.h"
#include "core/csv.h"
#include "core/error.h"
#include "core/provenance.h"
#include "core/timer.h"
#include "edit/edit_io.h"
#include "edit/transform.h"
#include "mesh/mesh_io.h"
#include "mesh/procedural.h"
#include "methods/deformer.h"
#include "methods/lri.h"
#include "methods/quality_metrics.h"

namespace fs = std::filesystem;
using namespace db;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Case {
  std::string name, family, source;
  Mesh mesh;
  Edit edit;                       // roles; edit.transform = the whole edit (single shot)
  std::optional<Points> ideal;     // analytic target, if any
  double angle_deg = 0;            // nominal edit angle, for the tables
  std::vector<Mat4> chain;         // non-empty: apply these one after another, re-resting after each
};

struct Config {
  std::string method, frames, ortho;
  std::string label() const { return method == "lri" ? fmt::format("lri-{}-{}", frames, ortho) : method; }
};

struct Result {
  Config config;
  std::string status = "ok";
  Points V;
  double init_s = 0, frame_s = 0;
  int fallbacks = -1;
  double sigma_min = -1;  // LRI: smallest singular value of any solved frame before orthonormalization
  std::size_t n_frames = 0, n_positions = 0, factor_bytes = 0;
};

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

// A bend case: fixed z <= z0, handle z >= z1, ideal_bend between; the handle transform is checked against the ideal.
Case bend_case(const std::string& name, const std::string& source, const Mesh& m, double z0, double z1, double deg) {
  Case c;
  c.name = name;
  c.family = "cylinder_bend";
  c.source = source;
  c.mesh = m;
  c.edit = axial_edit(m, z0, z1, name);
  // Bend exactly between the last fixed and the first handle vertex so that both constraints match the ideal.
  double zf = -1e300, zh = 1e300;
  for (int v = 0; v < m.num_vertices(); ++v) {
    if (c.edit.roles[v] == Role::Fixed) zf = std::max(zf, m.V(v, 2));
    if (c.edit.roles[v] == Role::Handle) zh = std::min(zh, m.V(v, 2));
  }
  const double a = deg * kPi / 180;
  c.edit.transform = bend_transform(a, zf, zh);
  c.ideal = ideal_bend(m.V, a, zf, zh);
  c.angle_deg = deg;
  const Points h = transformed(m.V, c.edit.transform);
  for (int v = 0; v < m.num_vertices(); ++v)
    if (c.edit.roles[v] == Role::Handle && (h.row(v) - c.ideal->row(v)).norm() > 1e-9 * bbox_diagonal(m.V))
      throw Error("bend_case: the handle transform does not match ideal_bend (convention changed?)");
  return c;
}

// CGAL's cylinder.off is a half tube of radius 1 around the x axis, x in [0, 3], z >= 0. Mapped by the proper
// rotation (x, y, z) -> (-y, -z, x): axis along +z, the material at y <= 0, so a bend towards +y (ideal_bend)
// keeps every fibre at R - y >= R > 0 (bending the other way would fold the 180-degree case through itself).
std::optional<Mesh> canonical_cgal_cylinder(const Mesh& raw, std::string& why) {
  Mesh m = raw;
  for (int v = 0; v < m.num_vertices(); ++v) m.V.row(v) << -raw.V(v, 1), -raw.V(v, 2), raw.V(v, 0);
  for (int v = 0; v < m.num_vertices(); ++v) {
    const double r = std::hypot(m.V(v, 0), m.V(v, 1));
    if (std::abs(r - 1) > 1e-3 || m.V(v, 1) > 1e-6 || m.V(v, 2) < -1e-6) {
      why = fmt::format("vertex {} is not on the unit half tube around the x axis this case assumes", v);
      return std::nullopt;
    }
  }
  m.name = raw.name;
  return m;
}

// Twist of `turns` full turns about the bar axis: fixed bottom cap, handle top cap.
Case twist_case(const Mesh& bar, double sz, int turns, double step_deg, bool chained) {
  Case c;
  c.family = "bar_twist";
  c.source = "make_bar";
  c.mesh = bar;
  const double total = 360.0 * turns;
  c.name = chained ? fmt::format("bar_twist{}", static_cast<int>(total)) : fmt::format("bar_twist{}_single", static_cast<int>(total));
  c.edit = axial_edit(bar, 0.0, sz, c.name);
  c.edit.transform = rotation_about_axis(Vec3::UnitZ(), total);
  c.ideal = ideal_twist(bar.V, total * kPi / 180, 0.0, sz);
  c.angle_deg = total;
  if (chained) {
    const int steps = static_cast<int>(std::ceil(total / step_deg - 1e-9));
    for (int s = 0; s < steps; ++s) c.chain.push_back(rotation_about_axis(Vec3::UnitZ(), total / steps));
  }
  return c;
}

Result run_config(const Case& c, const Config& cfg, unsigned seed) {
  Result r;
  r.config = cfg;
  DeformOptions o;
  o.method = cfg.method;
  if (cfg.method == "lri") {
    o.lri_frames = cfg.frames;
    o.lri_orthonormalize = cfg.ortho;
    o.lri_seed = seed;
  }
  // After each deform(): times and sizes sum / report over the chain's steps; frame_fallbacks is the last step's,
  // sigma_min the minimum over all steps.
  auto note = [&](const Deformer& d) {
    r.init_s += d.times().init();
    r.frame_s += d.times().frame();
    if (auto* l = dynamic_cast<const LriDeformer*>(&d)) {
      r.fallbacks = l->rest_frames().fallbacks;
      // 1 for a rotation; near 0 where least squares averaged opposite rotations (the frame collapsed).
      double sm = r.sigma_min < 0 ? 1e300 : r.sigma_min;
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
  };
  try {
    if (c.chain.empty()) {
      auto d = make_deformer(c.mesh, c.edit, o);
      r.V = d->deform(c.edit.transform);
      note(*d);
    } else {
      Mesh cur = c.mesh;
      for (const Mat4& step : c.chain) {
        auto d = make_deformer(cur, c.edit, o);  // rebuilt on the previous result: a new rest pose per step
        cur.V = d->deform(step);
        note(*d);
      }
      r.V = cur.V;
    }
  } catch (const std::exception& e) {
    r.status = fmt::format("error (exit {}): {}", exit_code(e), e.what());
    r.V.resize(0, 3);
  }
  return r;
}

std::string opt_num(const std::optional<double>& v) { return v ? num(*v) : "n/a"; }

struct Summary {  // what the verdict needs, per case
  std::string name, family;
  double angle = 0;
  bool has_ideal = false;
  std::map<std::string, double> ideal_rms, edge, arap, detail;  // by config label
  double strat_polar = 0, strat_gs = 0, ortho_gap = 0;  // max over strategies (relative to diag)
  std::map<std::string, double> strat_gs_by;             // GS: strategy -> max diff vs first
  double sigma_min = 1;                                   // over the LRI polar rows (GS may have failed)
  int errors = 0, lri_gs_errors = 0;
  std::string protocol;
};

}  // namespace

int main(int argc, char** argv) {
  try {
    const Args a = parse_args(argc, argv, 1, {"--no-meshes"});
    const fs::path data = a.get("--data", "data"), shared = a.get("--shared", "data/bs08");
    const std::string out = a.get("--out", "results/frames.csv");
    const std::string md = a.get("--md", (fs::path(out).parent_path() / "frames.md").string());
    const std::string mesh_dir = a.has("--no-meshes") ? "" : a.get("--meshes", "results/meshes/frames");
    const double step_deg = a.number("--twist-step", 30);
    const std::string only = a.get("--only", "");
    const unsigned seed = static_cast<unsigned>(a.number("--seed", 1));
    if (!(step_deg > 0 && step_deg <= 180)) throw InputError("--twist-step must be in (0, 180] degrees");
    if (!mesh_dir.empty()) fs::create_directories(mesh_dir);

    std::vector<Case> cases;
    auto want = [&](const std::string& name) { return only.empty() || name.find(only) != std::string::npos; };
    auto skip = [](const std::string& what, const std::string& why) {
      std::cerr << "[frames] skipping " << what << ": " << why << "\n";
    };

    // Procedural cylinders, radius 1, height 10: fixed z <= 2, handle z >= 8, a bend over length about 6.5 (R >= 2 at
    // 180 degrees, so the ideal stays embedded). Two resolutions: the frame choice may matter more on coarse rings.
    // An even ring count keeps every ring off the middle of the bend, where the LRI frame solve of an exact
    // 180-degree bend is singular (see frames.md); cyl31x16_bend180_symmetric puts a ring there on purpose.
    for (auto [rings, segs] : {std::pair{30, 16}, std::pair{60, 32}}) {
      const Mesh m = make_cylinder(rings, segs, 1.0, 10.0);
      for (double deg : {90.0, 180.0}) {
        const std::string name = fmt::format("cyl{}x{}_bend{}", rings, segs, static_cast<int>(deg));
        if (want(name)) cases.push_back(bend_case(name, "make_cylinder", m, 2.0, 8.0, deg));
      }
    }
    if (want("cyl31x16_bend180_symmetric"))
      cases.push_back(bend_case("cyl31x16_bend180_symmetric", "make_cylinder", make_cylinder(31, 16, 1.0, 10.0), 2.0,
                                8.0, 180.0));
    const fs::path cgal_cyl = data / "meshes" / "cylinder.off";
    if (want("cgal_cyl")) {
      if (!fs::exists(cgal_cyl)) {
        skip("the CGAL cylinder", cgal_cyl.string() + " missing (run scripts/data.sh)");
      } else {
        std::string why;
        const auto m = canonical_cgal_cylinder(read_mesh(cgal_cyl.string()), why);
        if (!m) skip("the CGAL cylinder", why);
        else
          for (double deg : {90.0, 180.0})  // fixed: first 3 rings (z <= 0.3), handle: last 3 rings (z >= 2.7)
            cases.push_back(bend_case(fmt::format("cgal_cyl_bend{}", static_cast<int>(deg)), cgal_cyl.string(), *m,
                                      0.3, 2.7, deg));
      }
    }
    // Bar 1 x 1 x 8 with 1/6 cells: 1226 vertices, closed.
    const double bar_len = 8.0;
    const Mesh bar = make_bar(6, 6, 48, 1.0, 1.0, bar_len);
    for (int turns : {1, 2, 3})
      if (want(fmt::format("bar_twist{}", 360 * turns))) cases.push_back(twist_case(bar, bar_len, turns, step_deg, true));
    if (want("bar_twist360_single")) cases.push_back(twist_case(bar, bar_len, 1, step_deg, false));
    const fs::path dino = data / "edits" / "dino_head.edit";
    if (want("dino_head")) {
      if (!fs::exists(data / "meshes" / "dino.off")) {
        skip("the dino head turn", (data / "meshes" / "dino.off").string() + " missing (run scripts/data.sh)");
      } else {
        EditCase ec = load_edit_case(dino.string());
        Case c;
        c.name = "dino_head90";
        c.family = "dino";
        c.source = dino.string();
        c.mesh = std::move(ec.mesh);
        c.edit = std::move(ec.edit);
        c.angle_deg = 90;
        cases.push_back(std::move(c));
      }
    }
    for (const char* b : {"plane", "cylinder", "bar", "cactus"}) {
      const std::string name = std::string("bs08_") + b;
      if (!want(name)) continue;
      if (!fs::exists(shared / (std::string(b) + ".off"))) {
        skip("BS08 " + std::string(b), "not found under " + shared.string());
        continue;
      }
      EditCase ec = load_edit_case((shared / b).string());
      Case c;
      c.name = name;
      c.family = "bs08";
      c.source = (shared / b).string();
      c.mesh = std::move(ec.mesh);
      c.edit = std::move(ec.edit);
      c.angle_deg = std::acos(std::clamp((c.edit.transform.topLeftCorner<3, 3>().trace() - 1) / 2, -1.0, 1.0)) * 180 / kPi;
      cases.push_back(std::move(c));
    }
    if (cases.empty()) throw InputError("no case selected");

    std::vector<Config> configs = {{"lap", "n/a", "n/a"}, {"tf", "n/a", "n/a"}};
    for (const char* o : {"gram_schmidt", "polar"})
      for (const char* f : {"first", "random", "height_angle", "curvature"}) configs.push_back({"lri", f, o});

    std::cerr << "[frames] " << provenance_summary() << "\n";
    CsvTable csv;
    std::vector<Summary> summaries;
    Timer total;
    for (const Case& c : cases) {
      Timer tc;
      const Adjacency adj = vertex_adjacency(c.mesh);
      const double diag = bbox_diagonal(c.mesh.V);
      const bool closed = is_closed(c.mesh.F);
      if (!mesh_dir.empty()) {
        const fs::path stem = fs::path(mesh_dir) / c.name;
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
      std::map<std::string, Result> results;
      for (const Config& cfg : configs) {
        Result r = run_config(c, cfg, seed);
        if (r.status == "ok" && !mesh_dir.empty()) {
          Mesh rm = c.mesh;
          rm.V = r.V;
          write_mesh((fs::path(mesh_dir) / (c.name + "__" + cfg.label() + ".ply")).string(), rm);
        }
        results.emplace(cfg.label(), std::move(r));
      }

      Summary s;
      s.name = c.name;
      s.family = c.family;
      s.angle = c.angle_deg;
      s.has_ideal = c.ideal.has_value();
      s.protocol = c.chain.empty() ? "single" : "chained";
      for (const Config& cfg : configs) {
        const Result& r = results.at(cfg.label());
        const bool ok = r.status == "ok";
        const bool lri = cfg.method == "lri";
        std::string ideal_rms = "n/a", ideal_max = "n/a", nd_mean = "n/a", nd_max = "n/a";
        std::string edge = "n/a", arap = "n/a", detail = "n/a", local = "n/a", vol = "n/a";
        std::string d_first_max = "n/a", d_first_rms = "n/a", d_polar_max = "n/a";
        if (ok) {
          // Normal-based metrics throw on a result with a vanished vertex normal (a collapsed 1-ring): "n/a" then.
          auto guarded = [&](const char* what, auto&& f) -> std::optional<double> {
            try {
              return f();
            } catch (const Error& e) {
              std::cerr << fmt::format("[frames] {} {}: {} n/a: {}\n", c.name, cfg.label(), what, e.what());
              return std::nullopt;
            }
          };
          const double e = edge_length_distortion(c.mesh.V, r.V, adj), ar = arap_energy(c.mesh.V, r.V, adj);
          const auto de = guarded("lri_detail_error", [&] { return lri_detail_error(c.mesh.V, r.V, c.mesh.F, adj); });
          edge = num(e);
          arap = num(ar);
          detail = opt_num(de);
          s.edge[cfg.label()] = e;
          s.arap[cfg.label()] = ar;
          if (de) s.detail[cfg.label()] = *de;
          local = opt_num(guarded("normal_dev_local",
                                  [&] { return local_normal_deviation(c.mesh.V, r.V, c.mesh.F, adj).mean_deg; }));
          if (closed) vol = opt_num(volume_change(c.mesh.V, r.V, c.mesh.F));
          if (c.ideal) {
            const DistanceStats ds = distance_between(r.V, *c.ideal, diag);
            ideal_rms = num(ds.rms);
            ideal_max = num(ds.max);
            s.ideal_rms[cfg.label()] = ds.rms;
            std::optional<AngleStats> nd;
            guarded("normal_dev_ideal", [&] {
              nd = normal_deviation(r.V, *c.ideal, c.mesh.F);
              return 0.0;
            });
            if (nd) {
              nd_mean = num(nd->mean_deg);
              nd_max = num(nd->max_deg);
            }
          }
          if (lri) {
            const Result& f = results.at(Config{"lri", "first", cfg.ortho}.label());
            const Result& p = results.at(Config{"lri", cfg.frames, "polar"}.label());
            if (f.status == "ok") {
              const DistanceStats df = distance_between(r.V, f.V, diag);
              d_first_max = num(df.max);
              d_first_rms = num(df.rms);
              if (cfg.ortho == "polar") s.strat_polar = std::max(s.strat_polar, df.max);
              else {
                s.strat_gs = std::max(s.strat_gs, df.max);
                s.strat_gs_by[cfg.frames] = df.max;
              }
            }
            if (p.status == "ok") {
              const double dp = distance_between(r.V, p.V, diag).max;
              d_polar_max = num(dp);
              s.ortho_gap = std::max(s.ortho_gap, dp);
            }
          }
          if (lri && cfg.ortho == "polar" && r.sigma_min >= 0) s.sigma_min = std::min(s.sigma_min, r.sigma_min);
        } else {
          ++s.errors;
          if (lri && cfg.ortho == "gram_schmidt") ++s.lri_gs_errors;
          std::cerr << fmt::format("[frames] {} {}: {}\n", c.name, cfg.label(), r.status);
        }
        csv.add({{"case", c.name},
                 {"family", c.family},
                 {"source", c.source},
                 {"mesh", c.mesh.name},
                 {"vertices", std::to_string(c.mesh.num_vertices())},
                 {"faces", std::to_string(c.mesh.num_faces())},
                 {"closed", closed ? "yes" : "no"},
                 {"handle", std::to_string(c.edit.count(Role::Handle))},
                 {"fixed", std::to_string(c.edit.count(Role::Fixed))},
                 {"free", std::to_string(c.edit.count(Role::Free))},
                 {"angle_deg", num(c.angle_deg)},
                 {"protocol", c.chain.empty() ? "single" : "chained"},
                 {"steps", std::to_string(c.chain.empty() ? 1 : c.chain.size())},
                 {"method", cfg.method},
                 {"frames", cfg.frames},
                 {"orthonormalize", cfg.ortho},
                 {"config", cfg.label()},
                 {"status", r.status},
                 {"ideal_rms", ideal_rms},
                 {"ideal_max", ideal_max},
                 {"edge_distortion", edge},
                 {"arap_energy", arap},
                 {"lri_detail_error", detail},
                 {"normal_dev_ideal_mean_deg", nd_mean},
                 {"normal_dev_ideal_max_deg", nd_max},
                 {"normal_dev_local_mean_deg", local},
                 {"volume_change", vol},
                 {"diff_vs_first_max", d_first_max},
                 {"diff_vs_first_rms", d_first_rms},
                 {"diff_vs_polar_max", d_polar_max},
                 {"frame_fallbacks", r.fallbacks >= 0 ? std::to_string(r.fallbacks) : "n/a"},
                 {"frame_sigma_min", r.sigma_min >= 0 ? num(r.sigma_min) : "n/a"},
                 {"n_frames_system", lri ? std::to_string(r.n_frames) : "n/a"},
                 {"n_positions_system", std::to_string(r.n_positions)},
                 {"factor_bytes", std::to_string(r.factor_bytes)},
                 {"init_s", num(r.init_s)},
                 {"frame_s", num(r.frame_s)}});
      }
      summaries.push_back(s);
      auto show = [&](const char* label) {
        auto it = s.ideal_rms.find(label);
        return it == s.ideal_rms.end() ? std::string("  n/a ") : fmt::format("{:.4f}", it->second);
      };
      std::cerr << fmt::format(
          "[frames] {:22s} {:5d} v  {:6.2f} s | ideal rms lap {} tf {} lri-first-gs {} lri-height-gs {} | strategy "
          "diff polar {:.1e} gs {:.1e}\n",
          c.name, c.mesh.num_vertices(), tc.seconds(), show("lap"), show("tf"), show("lri-first-gram_schmidt"),
          show("lri-height_angle-gram_schmidt"), s.strat_polar, s.strat_gs);
    }
    csv.write(out);
    std::cerr << fmt::format("[frames] wrote {} ({} rows) in {:.1f} s\n", out, csv.size(), total.seconds());

    // ---------------------------------------------------------------- verdict
    // Regular cases: every solved frame kept some rank (sigma_min >= 1e-3). Where a frame collapses the rotation it
    // is orthonormalized to is decided by round-off, so strategies can differ there even with polar.
    constexpr double kCollapsed = 1e-3;
    double max_polar = 0, max_polar_degenerate = 0, max_gs = 0, max_gap = 0;
    std::string where_gs, where_polar_degenerate;
    std::vector<std::string> degenerate;
    for (const auto& s : summaries) {
      const bool regular = s.sigma_min >= kCollapsed;
      if (regular) max_polar = std::max(max_polar, s.strat_polar);
      else {
        degenerate.push_back(s.name);
        if (s.strat_polar >= max_polar_degenerate) {
          max_polar_degenerate = s.strat_polar;
          where_polar_degenerate = s.name;
        }
      }
      if (s.strat_gs > max_gs) {
        max_gs = s.strat_gs;
        where_gs = s.name;
      }
      max_gap = std::max(max_gap, s.ortho_gap);
    }
    auto f3 = [](double v) { return fmt::format("{:.3g}", v); };
    auto find = [&](const std::string& name) -> const Summary* {
      for (const auto& s : summaries)
        if (s.name == name) return &s;
      return nullptr;
    };
    auto cell = [&](const std::map<std::string, double>& m, const std::string& k) {
      auto it = m.find(k);
      return it == m.end() ? std::string("n/a") : fmt::format("{:.4f}", it->second);
    };
    int better = 0, worse = 0, ties = 0;  // thesis 4.3: height-angle frames against first-neighbour frames (GS)
    for (const auto& s : summaries) {
      auto f = s.ideal_rms.find("lri-first-gram_schmidt"), h = s.ideal_rms.find("lri-height_angle-gram_schmidt");
      if (f == s.ideal_rms.end() || h == s.ideal_rms.end()) continue;
      const double rel = (h->second - f->second) / std::max(f->second, 1e-300);
      if (rel < -0.01) ++better;
      else if (rel > 0.01) ++worse;
      else ++ties;
    }
    int errors = 0;
    for (const auto& s : summaries) errors += s.errors;

    std::ostringstream o;
    o << "# Does the LRI frame choice change the result?\n\n";
    o << "Generated by `exp_frames` together with `" << fs::path(out).filename().string() << "` (" << csv.size()
      << " rows, " << summaries.size() << " cases, " << fmt::format("{:.0f}", total.seconds()) << " s); "
      << provenance_summary() << ". Every number below is a column of that CSV: distances are relative to the "
         "rest bounding-box diagonal.\n\n";

    o << "## Short answer\n\n";
    o << "- **Polar orthonormalization: no.** The four strategies (first neighbour, random neighbour, largest height "
         "angle, curvature direction) give the same mesh up to round-off: largest vertex difference to the "
         "first-neighbour result "
      << f3(max_polar) << " over the " << summaries.size() - degenerate.size() << " cases whose solved frames keep their rank";
    if (!degenerate.empty()) {
      o << "; in the " << degenerate.size() << " case(s) where some solved frame collapses (smallest singular value "
           "below "
        << f3(kCollapsed) << ": ";
      for (std::size_t i = 0; i < degenerate.size(); ++i) o << (i ? ", " : "") << "`" << degenerate[i] << "`";
      o << ") round-off picks the rotation and the strategies differ by up to " << f3(max_polar_degenerate) << " (`"
        << where_polar_degenerate << "`)";
    }
    o << ".\n";
    o << "- **Gram-Schmidt (b1 first): " << (max_gs > 1e-8 ? "yes" : "no") << ".** The strategies differ by up to "
      << f3(max_gs) << " (`" << where_gs << "`); Gram-Schmidt and polar differ by up to " << f3(max_gap)
      << " for the same strategy. Against the analytic ideal the thesis' height-angle frames (eq. 4-4) beat "
         "first-neighbour frames by more than 1% RMS in "
      << better << " case(s), lose in " << worse << " and tie within 1% in " << ties << ".\n";
    for (const char* name : {"cyl60x32_bend90", "cyl60x32_bend180"})
      if (const Summary* c = find(name)) {
        o << "- **" << fmt::format("{:g}", c->angle) << "-degree bend of the 60x32 cylinder**, RMS distance to the "
          << "ideal: LAP " << cell(c->ideal_rms, "lap") << ", TF " << cell(c->ideal_rms, "tf") << ", LRI first/GS "
          << cell(c->ideal_rms, "lri-first-gram_schmidt") << ", LRI height-angle/GS "
          << cell(c->ideal_rms, "lri-height_angle-gram_schmidt") << ", LRI curvature/GS "
          << cell(c->ideal_rms, "lri-curvature-gram_schmidt") << ", LRI polar (any strategy) "
          << cell(c->ideal_rms, "lri-first-polar") << "; smallest singular value of a solved LRI frame "
          << f3(c->sigma_min) << ".";
        if (c->sigma_min < 0.1)
          o << " The frames nearly collapse at mid-length, where the tube kinks instead of bending (point 4 below; "
               "`plots/render_"
            << c->name << ".png`).";
        o << "\n";
      }
    o << "\n";

    o << "## The algebra\n\n"
         "Write the rest frame of vertex i as F_i = [b1 b2 N] (orthonormal), the connection R_ij = F_i^T F_j "
         "(eqs. 3-16, 3-17) and the discrete forms d_ij = F_i^T (x_j - x_i) (eqs. 3-12, 3-13). Per world "
         "component c the frame system minimizes sum_(i,j) |u_j - R_ij^T u_i|^2 over u_i = row c of the unknown "
         "frame F'_i.\n\n"
         "1. **The rest frames drop out of the frame solve.** Substitute F'_i = W_i F_i, i.e. u_i = F_i^T w_i with "
         "w_i = row c of W_i: u_j - R_ij^T u_i = F_j^T (w_j - w_i), whose norm is |w_j - w_i|. The frame energy is "
         "the graph Laplacian energy of W, and the constraints read W = R_h on the handle and W = I on fixed "
         "vertices. So F'_i = W_i F_i with W the harmonic blend of the constraint rotations - for one handle, "
         "W_i = I + h_i (R_h - I) with h the discrete harmonic function (0 fixed, 1 handle) - whatever b1 (or even "
         "N) was chosen. Another b1 is F_i Z_i with Z_i a rotation about N_i; the solved frame becomes W_i F_i Z_i "
         "and the forms Z_i^T d_ij (`tests/lri_test.cpp`: PolarResultDoesNotDependOnTheFrameStrategy, "
         "FrameSolveIsAHarmonicBlendOfRotations).\n"
         "2. **Orthonormalization decides.** The position targets are orth(W_i F_i Z_i) Z_i^T d_ij. The polar factor "
         "commutes with orthogonal factors on the right, orth(W F Z) = orth(W) F Z, so the targets are orth(W_i) "
         "(x_j - x_i) for every strategy: LRI with polar orthonormalization is a harmonic rotation blend followed "
         "by a Poisson reconstruction, independent of the frames. Gram-Schmidt keeps the direction of the first "
         "column, W_i b1_i, which differs between strategies whenever W_i is not a scaled rotation (it is not: "
         "a linear blend of rotations shrinks and shears).\n"
         "3. **Where differences come from:** (a) the orthonormalization order (Gram-Schmidt), measured below; "
         "(b) weights that depend on the frame axes (none here: every edge weighs 1; any weight symmetric in i, j "
         "and computed from the geometry keeps point 1); (c) constraints that are not frames of one rotation per "
         "vertex (soft constraint weights do not matter, they transform like the energy); (d) round-off, which is "
         "harmless unless W_i is singular.\n"
         "4. **W is singular at 180 degrees.** For a half turn about axis a, W = aa^T + (1 - 2h)(I - aa^T): the "
         "singular values are 1 and |1 - 2h| (twice), zero on the level set h = 1/2. polar(W) jumps from I to R_h "
         "across it, so the reconstruction kinks there instead of bending; Gram-Schmidt breaks down on a vertex "
         "exactly on the level set (b1 vanishes: SolverError, case `cyl31x16_bend180_symmetric`) and near it "
         "snaps b1 to the axis. No choice of b1 repairs this: the linear frame solve cannot represent rotations of "
         "180 degrees or more, and chained edits (the twists) are the linear way around it.\n\n";

    o << "## Measured: strategy against strategy\n\n"
         "`diff_vs_first_max`: largest vertex distance between a strategy's result and the first-neighbour result "
         "with the same orthonormalization. `diff_vs_polar_max`: Gram-Schmidt against polar, same strategy "
         "(maximum over strategies). `frame_sigma_min`: smallest singular value of any solved frame (1 for a "
         "rotation).\n\n";
    o << "| case | protocol | frame sigma min | polar: max over strategies | GS: random | GS: height_angle | "
         "GS: curvature | GS vs polar | LRI failures |\n|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& s : summaries) {
      auto gs = [&](const char* k) {
        auto it = s.strat_gs_by.find(k);
        return it == s.strat_gs_by.end() ? std::string("n/a") : f3(it->second);
      };
      o << "| " << s.name << " | " << s.protocol << " | " << f3(s.sigma_min) << " | " << f3(s.strat_polar) << " | "
        << gs("random") << " | " << gs("height_angle") << " | " << gs("curvature") << " | " << f3(s.ortho_gap)
        << " | " << s.lri_gs_errors << " |\n";
    }

    o << "\n## Measured: distance to the analytic ideal\n\n"
         "`ideal_rms`: RMS vertex distance to the analytic deformation. Twists are chains of edits of at most "
      << f3(step_deg)
      << " degrees, each re-using the previous result as rest mesh; `bar_twist360_single` is one 360-degree "
         "transform, which every linear method receives as the identity.\n\n";
    const std::vector<std::string> cols = {"lap",
                                           "tf",
                                           "lri-first-gram_schmidt",
                                           "lri-random-gram_schmidt",
                                           "lri-height_angle-gram_schmidt",
                                           "lri-curvature-gram_schmidt",
                                           "lri-first-polar"};
    o << "| case |";
    for (const auto& c : cols) o << " " << c << " |";
    o << "\n|---|";
    for (std::size_t i = 0; i < cols.size(); ++i) o << "---|";
    o << "\n";
    for (const auto& s : summaries) {
      if (!s.has_ideal) continue;
      o << "| " << s.name << " |";
      for (const auto& c : cols) o << " " << cell(s.ideal_rms, c) << " |";
      o << "\n";
    }
    o << "\nLocal rigidity (`arap_energy`, relative) and LRI detail error (`lri_detail_error`), every case:\n\n";
    o << "| case | ARAP lap | ARAP tf | ARAP lri-first-gs | ARAP lri-height-gs | ARAP lri-polar | detail lap | "
         "detail tf | detail lri-first-gs | detail lri-height-gs | detail lri-polar |\n"
         "|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& s : summaries) {
      o << "| " << s.name;
      for (const auto* m : {&s.arap, &s.detail})
        for (const char* k : {"lap", "tf", "lri-first-gram_schmidt", "lri-height_angle-gram_schmidt", "lri-first-polar"})
          o << " | " << cell(*m, k);
      o << " |\n";
    }

    o << "\n## Other measured observations\n\n";
    const Summary* t1 = find("bar_twist360");
    const Summary* t1s = find("bar_twist360_single");
    if (t1 && t1s)
      o << "- A chained full twist leaves LAP where it started: LAP's result is linear in the handle positions, and "
           "the steps' handle displacements sum to zero over a full turn. `ideal_rms` of LAP, chained: "
        << cell(t1->ideal_rms, "lap") << "; of the single 360-degree transform (the rest mesh for every method): "
        << cell(t1s->ideal_rms, "lap") << ". TF and LRI are rebuilt on every step's result, so the chain is not linear "
           "for them: LRI first/GS "
        << cell(t1->ideal_rms, "lri-first-gram_schmidt") << ", LRI polar " << cell(t1->ideal_rms, "lri-first-polar")
        << ", TF " << cell(t1->ideal_rms, "tf") << ".\n";
    if (errors > 0)
      o << "- " << errors << " configuration(s) failed; their rows carry the error in `status`.\n";
    o << "- Renders: `plots/render_<case>.png` (plots/render_meshes.py), figures: `plots/frames_*.png` "
         "(plots/frames.py).\n";
    write_atomically(md, [&](std::ostream& os) { os << o.str(); });
    std::cerr << "[frames] wrote " << md << "\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "exp_frames: error: " << e.what() << "\n";
    return exit_code(e);
  }
}
