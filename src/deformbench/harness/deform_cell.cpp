#include "harness/deform_cell.h"

#include <fmt/format.h>

#include "core/error.h"
#include "core/resources.h"
#include "edit/edit_io.h"
#include "harness/stats.h"
#include "mesh/mesh_io.h"
#include "methods/deformer.h"
#include "methods/drag.h"

namespace db::harness {
namespace {

// The frames of the drag: per-frame phase times (medians go to the result) and the last frame's positions.
struct Drag {
  std::vector<double> frame, rhs, solve, write;
  Points V;
};

Drag drag(Deformer& d, const Mat4& T, int frames) {
  Drag g;
  for (int f = 1; f <= frames; ++f) {
    g.V = d.deform(interpolate_transform(T, static_cast<double>(f) / frames));
    const PhaseTimes& t = d.times();
    g.frame.push_back(t.frame());
    g.rhs.push_back(t.rhs);
    g.solve.push_back(t.solve);
    g.write.push_back(t.write);
  }
  return g;
}

DeformOptions options_of(const DeformCell& c) {
  DeformOptions o;
  o.method = c.method;
  o.constraints = parse_constraints(c.constraints);
  o.build = parse_build(c.build);
  o.solver = c.backend;
  o.solver_options.ordering = c.ordering;
  o.solver_options.factor_dir = c.factor_dir;
  o.memory_budget = c.memory_budget_bytes;
  return o;
}

void add_system(CellResult& r, const Deformer& d) {
  const SystemReport& s = d.systems().front();
  r.set("n", static_cast<double>(s.n), "count");
  r.set("nnz", static_cast<double>(s.nnz), "count");
  r.set("nnz_factor", static_cast<double>(s.factor.nnz_factor), "count");
  r.set("factor_flops", s.factor.flops, "flop");
  r.set("min_pivot_ratio", s.factor.min_pivot_ratio, "ratio");
  r.set_text("ordering_used", s.factor.ordering_used);
  const PhaseTimes& t = d.times();
  r.set("build_s", t.build, "s");
  r.set("analyze_s", t.analyze, "s");
  r.set("factorize_s", t.factorize, "s");
  r.set("init_s", t.init(), "s");
}

void add_memory(CellResult& r, const Deformer& d) {
  r.set("matrix_bytes", static_cast<double>(d.matrix_bytes()), "bytes");
  r.set("factor_bytes", static_cast<double>(d.factor_bytes()), "bytes");
  double held = 0;
  for (const auto& [name, bytes] : d.systems().front().held_bytes) {
    r.set("held_bytes:" + name, static_cast<double>(bytes), "bytes");
    held += static_cast<double>(bytes);
  }
  r.set("held_total_bytes", held, "bytes");
}

}  // namespace

CellSpec DeformCell::to_spec() const {
  CellSpec s("deform");
  s.set("model", model);
  if (!mesh.empty()) s.set("mesh", mesh);
  if (!edit.empty()) s.set("edit", edit);
  s.set("method", method).set("build", build).set("backend", backend).set("ordering", ordering);
  s.set("constraints", constraints).set("frames", frames);
  if (!mesh.empty()) s.set("handle", thesis.handle_count).set("anchors", thesis.anchor_count).set("drag", thesis.drag_fraction);
  if (!factor_dir.empty()) s.set("factor_dir", factor_dir);
  if (memory_budget_bytes > 0) s.set("memory_budget_bytes", memory_budget_bytes);
  if (!out_mesh.empty()) s.set("out_mesh", out_mesh);
  return s;
}

DeformCell DeformCell::from_spec(const CellSpec& s) {
  s.check_keys({"model", "mesh", "edit", "method", "build", "backend", "ordering", "constraints", "frames", "handle",
                "anchors", "drag", "factor_dir", "memory_budget_bytes", "out_mesh"});
  DeformCell c;
  c.mesh = s.get("mesh", "");
  c.edit = s.get("edit", "");
  if (c.mesh.empty() == c.edit.empty()) throw UsageError("deform cell: give exactly one of mesh= and edit=");
  c.model = s.get("model", c.mesh.empty() ? c.edit : c.mesh);
  c.method = s.get("method", c.method);
  c.build = s.get("build", c.build);
  c.backend = s.get("backend", c.backend);
  c.ordering = s.get("ordering", c.ordering);
  c.constraints = s.get("constraints", c.constraints);
  c.factor_dir = s.get("factor_dir", "");
  c.out_mesh = s.get("out_mesh", "");
  c.frames = static_cast<int>(s.integer("frames", c.frames, 1, 100000));
  c.thesis.handle_count = static_cast<int>(s.integer("handle", c.thesis.handle_count, 1, 1 << 30));
  c.thesis.anchor_count = static_cast<int>(s.integer("anchors", c.thesis.anchor_count, 1, 1 << 30));
  c.thesis.drag_fraction = s.real("drag", c.thesis.drag_fraction, -1e3, 1e3);
  c.memory_budget_bytes = static_cast<std::size_t>(s.real("memory_budget_bytes", 0, 0, 1e18));
  return c;
}

std::string DeformCell::key() const { return fmt::format("{}/{}/{}/{}", model, method, build, backend); }

CellResult measure_deform_cell(const CellSpec& spec) {
  const DeformCell c = DeformCell::from_spec(spec);
  EditCase ec;
  if (!c.edit.empty()) {
    ec = load_edit_case(c.edit);
  } else {
    ec.mesh = read_mesh(c.mesh);
    validate_mesh(ec.mesh);
    ec.edit = make_thesis_edit(ec.mesh, c.thesis);
  }
  CellResult r;
  r.set("vertices", ec.mesh.num_vertices(), "count");
  r.set("faces", ec.mesh.num_faces(), "count");
  r.set("handle", ec.edit.count(Role::Handle), "count");
  r.set("fixed", ec.edit.count(Role::Fixed), "count");
  r.set("baseline_rss_bytes", static_cast<double>(current_rss_bytes()), "bytes");
  const DeformOptions o = options_of(c);
  r.set_text("mesh_name", ec.mesh.name);
  r.set_text("constraints", to_string(o.constraints));
  r.set_text("build", to_string(o.build));
  r.set_text("backend", o.solver);

  auto d = make_deformer(ec.mesh, ec.edit, o);
  const Drag g = drag(*d, ec.edit.transform, c.frames);
  add_system(r, *d);
  r.set("frames", c.frames, "count");
  r.set("frame_s", median(g.frame), "s");
  r.set("rhs_s", median(g.rhs), "s");
  r.set("solve_s", median(g.solve), "s");
  r.set("write_s", median(g.write), "s");
  r.set("fps", 1.0 / r.get("frame_s"), "1/s");
  add_memory(r, *d);
  r.set("mean_displacement", (g.V - ec.mesh.V).rowwise().norm().mean() / bbox_diagonal(ec.mesh.V), "bbox_diagonal");
  r.set("peak_rss_bytes", static_cast<double>(peak_rss_bytes()), "bytes");
  if (!c.out_mesh.empty()) {
    Mesh m = ec.mesh;
    m.V = g.V;
    write_mesh(c.out_mesh, m);
  }
  return r;
}

}  // namespace db::harness
