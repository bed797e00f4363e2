#include "harness/deform_cell.h"

#include <algorithm>

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "solvers/base/resources.h"
#include "edit/edit_io.h"
#include "harness/cpu_timer.h"
#include "harness/machine_rates.h"
#include "mesh/mesh_io.h"
#include "methods/deformer.h"
#include "methods/deform_record.h"
#include "methods/drag.h"

namespace db::harness {
namespace {

// The deformation's record (methods/deform_record.h) as the cell's measures and strings.
void add_record(CellResult& r, const DeformRecord& record) {
  for (const RecordField& f : record)
    if (f.is_text())
      r.set_text(f.name, f.text);
    else
      r.set(f.name, f.value, f.unit);
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

// The same drag in handle mode on the factored systems, and how far its last frame lies from the full mode's.
void add_handle_frames(CellResult& r, Deformer& d, const Edit& e, int frames, const Points& full) {
  const CpuTimer cpu;
  d.precompute_handle_frames();
  const double precompute_cpu = cpu.seconds();
  if (d.frame_mode() != FrameMode::Handle)  // per-vertex targets over the handle limit: no handle frames to pair
    throw InputError(d.frame_mode_note());
  const Drag g = drag(d, e, frames);
  const PhaseTimes& t = d.times();
  r.set("precompute_s", t.precompute, "s");
  r.set("precompute_cpu_s", precompute_cpu, "s");
  r.set("init_precompute_s", t.init() + t.precompute, "s");
  set_spread(r, "frame_handle_s", g.frame);
  set_spread(r, "response_s", g.response);
  set_spread(r, "handle_rhs_s", g.rhs);  // lri: orthonormalization + position right-hand side
  set_spread(r, "handle_solve_s", g.solve);  // lri: the position solve
  set_spread(r, "orthonormalize_s", g.orthonormalize);
  r.set("fps_handle", 1.0 / r.get("frame_handle_s"), "1/s");
  r.set("response_bytes", static_cast<double>(d.response_bytes()), "bytes");
  r.set("handle_vs_full", (g.V - full).rowwise().norm().maxCoeff() / bbox_diagonal(full), "bbox_diagonal");
  r.set("peak_rss_handle_bytes", static_cast<double>(peak_rss_bytes()), "bytes");
  // The floor of a handle frame: one pass over the responses at the rate the worker threads read memory now.
  const double read = MachineRates::read_bandwidth();
  r.set("memory_read", read / 1e9, "GB/s");
  r.set("response_pass_s", static_cast<double>(d.response_bytes()) / read, "s");
}

}  // namespace

DeformOptions DeformCell::default_options() {
  DeformOptions o;
  o.method = Method::Tf;
  o.solver = "multifrontal";
  return o;
}

namespace {
const std::vector<std::string> kCellKeys = {"model", "mesh", "edit", "frames", "handle", "anchors", "drag",
                                            "memory_budget_bytes", "out_mesh", "handle_frames"};
}  // namespace

CellSpec DeformCell::to_spec() const {
  CellSpec s("deform");
  s.set("model", model);
  if (!mesh.empty()) s.set("mesh", mesh);
  if (!edit.empty()) s.set("edit", edit);
  s.set("method", method()).set("build", build()).set("backend", backend());  // the cell's key, always written
  for (const auto& [key, value] : deform_option_items(options)) s.set(key, value);
  s.set("frames", frames);
  if (!mesh.empty()) s.set("handle", thesis.handle_count).set("anchors", thesis.anchor_count).set("drag", thesis.drag_fraction);
  if (memory_budget_bytes > 0) s.set("memory_budget_bytes", memory_budget_bytes);
  if (!out_mesh.empty()) s.set("out_mesh", out_mesh);
  if (handle_frames) s.set("handle_frames", 1);
  return s;
}

DeformCell DeformCell::from_spec(const CellSpec& s) {
  std::vector<std::string> known = kCellKeys, given;
  for (const DeformOptionDef& d : deform_option_defs()) known.push_back(d.key);
  s.check_keys(known);
  DeformCell c;
  c.mesh = s.get("mesh", "");
  c.edit = s.get("edit", "");
  if (c.mesh.empty() == c.edit.empty()) throw UsageError("deform cell: give exactly one of mesh= and edit=");
  c.model = s.get("model", c.mesh.empty() ? c.edit : c.mesh);
  for (const auto& [key, value] : s.items())
    if (key != "kind" && std::find(kCellKeys.begin(), kCellKeys.end(), key) == kCellKeys.end()) {
      set_deform_option(c.options, key, value);
      given.push_back(key);
    }
  c.options = resolve_options(c.options, given);
  c.out_mesh = s.get("out_mesh", "");
  c.frames = static_cast<int>(s.integer("frames", c.frames, 1, 100000));
  c.thesis.handle_count = static_cast<int>(s.integer("handle", c.thesis.handle_count, 1, 1 << 30));
  c.thesis.anchor_count = static_cast<int>(s.integer("anchors", c.thesis.anchor_count, 1, 1 << 30));
  c.thesis.drag_fraction = s.real("drag", c.thesis.drag_fraction, -1e3, 1e3);
  c.memory_budget_bytes = static_cast<std::size_t>(s.real("memory_budget_bytes", 0, 0, 1e18));
  c.handle_frames = s.integer("handle_frames", 0, 0, 1) == 1;
  return c;
}

std::string DeformCell::key() const { return fmt::format("{}/{}/{}/{}", model, method(), build(), backend()); }

CellResult measure_deform_cell(const CellSpec& spec) {
  const DeformCell c = DeformCell::from_spec(spec);
  EditCase ec;
  if (!c.edit.empty()) {
    ec = load_edit_case(c.edit);
  } else {
    ec.mesh = read_mesh(c.mesh);
    validate_mesh(ec.mesh, Manifold::Allowed);  // make_deformer refuses what the method cannot take
    ec.edit = make_thesis_edit(ec.mesh, c.thesis);
  }
  CellResult r;
  r.set("baseline_rss_bytes", static_cast<double>(current_rss_bytes()), "bytes");
  DeformOptions o = c.options;
  if (c.memory_budget_bytes > 0) o.memory_budget = c.memory_budget_bytes;

  const CpuTimer init_cpu;
  auto d = make_deformer(ec.mesh, ec.edit, o);
  const double init_cpu_s = init_cpu.seconds();
  const Drag g = drag(*d, ec.edit, c.frames);
  add_record(r, deform_record(ec.mesh, ec.edit, o, *d, g));
  r.set("init_cpu_s", init_cpu_s, "s");  // make_deformer: the init phases (and the input checks) in CPU time
  set_spread(r, "frame_cpu_s", g.frame_cpu);
  r.set("fps", 1.0 / r.get("frame_s"), "1/s");
  add_memory(r, *d);
  r.set("mean_displacement", (g.V - ec.mesh.V).rowwise().norm().mean() / bbox_diagonal(ec.mesh.V), "bbox_diagonal");
  // The thesis' memory is the full mode's: the peak before the responses (and the read-rate probe's array) exist.
  r.set("peak_rss_bytes", static_cast<double>(peak_rss_bytes()), "bytes");
  if (c.handle_frames) add_handle_frames(r, *d, ec.edit, c.frames, g.V);
  if (!c.out_mesh.empty()) {
    Mesh m = ec.mesh;
    m.V = g.V;
    write_mesh(c.out_mesh, m);
  }
  return r;
}

}  // namespace db::harness
