#include "methods/deform_record.h"

#include <limits>

namespace db {

void add_number(DeformRecord& r, const std::string& name, double value, const std::string& unit) {
  r.push_back({name, value, unit, ""});
}

void add_text(DeformRecord& r, const std::string& name, const std::string& text) { r.push_back({name, 0, "text", text}); }

void add_spread(DeformRecord& r, const std::string& name, const std::vector<double>& samples) {
  const Spread s = spread(samples);
  add_number(r, name, s.median, "s");
  add_number(r, spread_name(name, "min"), s.min, "s");
  add_number(r, spread_name(name, "max"), s.max, "s");
  add_number(r, spread_name(name, "reps"), s.count > 0 ? s.count : std::numeric_limits<double>::quiet_NaN(), "count");
}

DeformRecord deform_record(const Mesh& mesh, const Edit& edit, const DeformOptions& o, const Deformer& d,
                           const Drag& g) {
  const SystemReport& sys = d.systems().front();
  const PhaseTimes& t = d.times();
  const bool refined = refines(sys.backend);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  DeformRecord r;
  add_text(r, "mesh", mesh.name);
  add_text(r, "edit", edit.name);
  add_text(r, "method", to_string(o.method));
  add_text(r, "weights", to_string(o.weights));
  add_text(r, "constraints", to_string(o.constraints));
  add_text(r, "build", to_string(o.build));
  add_text(r, "backend", sys.backend);  // what factored it
  add_text(r, "ordering_used", sys.factor.ordering_used);
  add_text(r, "factor_storage", sys.factor.factor_on_disk ? "disk" : "memory");
  add_text(r, "drag", edit.targets.rows() > 0 ? "per_vertex" : "affine");
  add_text(r, "frame_mode", to_string(d.frame_mode()));
  add_text(r, "precision", sys.backend == kMixedBackend ? "mixed" : "double");
  add_number(r, "vertices", mesh.num_vertices(), "count");
  add_number(r, "faces", mesh.num_faces(), "count");
  add_number(r, "handle", edit.count(Role::Handle), "count");
  add_number(r, "fixed", edit.count(Role::Fixed), "count");
  add_number(r, "n", static_cast<double>(sys.n), "count");
  add_number(r, "nnz", static_cast<double>(sys.nnz), "count");
  add_number(r, "nnz_factor", static_cast<double>(sys.factor.nnz_factor), "count");
  add_number(r, "factor_flops", sys.factor.flops, "flop");
  add_number(r, "factor_top_flops", sys.factor.top_flops, "flop");
  add_number(r, "min_pivot_ratio", sys.factor.min_pivot_ratio, "ratio");
  add_number(r, "build_s", t.build, "s");
  add_number(r, "analyze_s", t.analyze, "s");
  add_number(r, "factorize_s", t.factorize, "s");
  add_number(r, "factorize_top_s", sys.factor.top_seconds, "s");
  add_number(r, "init_s", t.init(), "s");
  const bool handle = d.frame_mode() == FrameMode::Handle;  // the responses' columns, else not measured
  add_number(r, "precompute_s", handle ? t.precompute : nan, "s");
  add_number(r, "frames", static_cast<double>(g.frame.size()), "count");
  add_spread(r, "frame_s", g.frame);
  add_spread(r, "rhs_s", g.rhs);
  add_spread(r, "solve_s", g.solve);
  add_spread(r, "write_s", g.write);
  add_spread(r, "response_s", handle ? g.response : std::vector<double>{});
  add_number(r, "response_bytes", handle ? static_cast<double>(d.response_bytes()) : nan, "bytes");
  add_number(r, "matrix_bytes", static_cast<double>(d.matrix_bytes()), "bytes");
  add_number(r, "factor_bytes", static_cast<double>(d.factor_bytes()), "bytes");
  add_number(r, "refine_iterations", refined ? sys.factor.iterations : nan, "count");
  add_number(r, "refine_residual", refined ? sys.factor.achieved_tolerance : nan, "ratio");
  add_number(r, "refine_correction", refined ? sys.factor.last_correction : nan, "ratio");
  add_number(r, "refine_tolerance", refined ? o.solver_options.tolerance : nan, "ratio");
  return r;
}

}  // namespace db
