#include "harness/cell.h"

#include <malloc.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <map>
#include <new>
#include <sstream>

#include <fmt/format.h>

#include "core/error.h"
#include "core/resources.h"
#include "harness/stats.h"
#include "harness/subprocess.h"
#include "mesh/mesh_io.h"
#include "methods/deformer.h"
#include "methods/drag.h"

namespace db::harness {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// One table drives encoding, decoding and the tidy rows, so a new field is added in one place.
struct Field {
  const char* name;
  const char* unit;
  double CellResult::*member;
  bool core;  // kept (as NaN) for cells that did not run
};
const std::vector<Field>& fields() {
  static const std::vector<Field> f = {
      {"vertices", "count", &CellResult::vertices, false},
      {"n", "count", &CellResult::n, false},
      {"nnz", "count", &CellResult::nnz, false},
      {"nnz_factor", "count", &CellResult::nnz_factor, false},
      {"factor_flops", "flop", &CellResult::factor_flops, false},
      {"min_pivot_ratio", "ratio", &CellResult::min_pivot_ratio, false},
      {"build_s", "s", &CellResult::build_s, true},
      {"analyze_s", "s", &CellResult::analyze_s, true},
      {"factorize_s", "s", &CellResult::factorize_s, true},
      {"init_s", "s", &CellResult::init_s, true},
      {"frames", "count", &CellResult::frames, false},
      {"frame_s", "s", &CellResult::frame_s, true},
      {"rhs_s", "s", &CellResult::rhs_s, false},
      {"solve_s", "s", &CellResult::solve_s, false},
      {"write_s", "s", &CellResult::write_s, false},
      {"fps", "1/s", &CellResult::fps, true},
      {"matrix_bytes", "bytes", &CellResult::matrix_bytes, true},
      {"factor_bytes", "bytes", &CellResult::factor_bytes, true},
      {"held_total_bytes", "bytes", &CellResult::held_total_bytes, true},
      {"peak_rss_bytes", "bytes", &CellResult::peak_rss_bytes, true},
      {"baseline_rss_bytes", "bytes", &CellResult::baseline_rss_bytes, false},
      {"mean_displacement", "bbox_diagonal", &CellResult::mean_displacement, false},
      {"ru_maxrss_bytes", "bytes", &CellResult::ru_maxrss_bytes, false},
      {"parent_rss_bytes", "bytes", &CellResult::parent_rss_bytes, false},
      {"cell_wall_s", "s", &CellResult::wall_s, false},
      {"runs", "count", &CellResult::runs, false},
  };
  return f;
}

double parse_double(const std::string& v) {
  if (v == "nan") return kNaN;
  std::size_t pos = 0;
  const double d = std::stod(v, &pos);
  if (pos != v.size()) throw Error("not a number: " + v);
  return d;
}

std::string fmt_double(double v) {
  if (std::isnan(v)) return "nan";
  return fmt::format("{}", v);
}

}  // namespace

CellResult::CellResult() {
  for (const Field& f : fields()) this->*f.member = kNaN;
}

std::string CellSpec::key() const { return fmt::format("{}/{}/{}/{}", model, system, build, backend_label()); }

std::vector<std::string> CellSpec::to_args() const {
  std::vector<std::string> args = {"--cell",
          "--model", model,
          "--mesh", mesh_path,
          "--system", system,
          "--build", build,
          "--backend", backend,
          "--ordering", ordering,
          "--frames", std::to_string(frames),
          "--handle", std::to_string(edit.handle_count),
          "--anchors", std::to_string(edit.anchor_count),
          "--drag", fmt::format("{}", edit.drag_fraction),
          "--memory-budget-bytes", std::to_string(memory_budget_bytes),
          "--address-space-limit", std::to_string(address_space_limit)};
  if (!factor_dir.empty()) args.insert(args.end(), {"--factor-dir", factor_dir});
  return args;
}

CellSpec CellSpec::from_args(const Args& a) {
  CellSpec s;
  for (const char* k : {"--model", "--mesh", "--system", "--build"})
    if (!a.has(k)) throw Error(fmt::format("cell: missing {}", k));
  s.model = a.get("--model", "");
  s.mesh_path = a.get("--mesh", "");
  s.system = a.get("--system", s.system);
  s.build = a.get("--build", s.build);
  s.backend = a.get("--backend", s.backend);
  s.ordering = a.get("--ordering", s.ordering);
  s.factor_dir = a.get("--factor-dir", s.factor_dir);
  s.frames = static_cast<int>(a.number("--frames", s.frames));
  s.edit.handle_count = static_cast<int>(a.number("--handle", s.edit.handle_count));
  s.edit.anchor_count = static_cast<int>(a.number("--anchors", s.edit.anchor_count));
  s.edit.drag_fraction = a.number("--drag", s.edit.drag_fraction);
  s.memory_budget_bytes = static_cast<std::size_t>(a.number("--memory-budget-bytes", 0));
  s.address_space_limit = static_cast<std::size_t>(a.number("--address-space-limit", 0));
  if (s.frames < 1) throw Error("cell: --frames must be >= 1");
  return s;
}

std::vector<Measure> measures(const CellResult& r) {
  std::vector<Measure> m;
  for (const Field& f : fields()) {
    const double v = r.*f.member;
    if (r.ok() || f.core || !std::isnan(v)) m.push_back({f.name, v, f.unit});
  }
  for (const auto& [name, bytes] : r.held_bytes) m.push_back({"held_bytes:" + name, bytes, "bytes"});
  const Prediction& p = r.predicted;
  m.push_back({"predicted_build_bytes", p.build_bytes, "bytes"});
  m.push_back({"predicted_factor_bytes", p.factor_bytes, "bytes"});
  m.push_back({"predicted_workspace_bytes", p.workspace_bytes, "bytes"});
  m.push_back({"predicted_bytes", p.total_bytes, "bytes"});
  m.push_back({"predicted_factor_nnz", p.factor_nnz, "count"});
  m.push_back({"predicted_factor_flops", p.factor_flops, "flop"});
  m.push_back({"predicted_s", p.seconds, "s"});
  return m;
}

std::string encode_result(const CellResult& r) {
  std::ostringstream o;
  o << "DBCELL status=" << pct_encode(r.status) << " message=" << pct_encode(r.message)
    << " ordering=" << pct_encode(r.ordering);
  for (const Field& f : fields()) o << ' ' << f.name << '=' << fmt_double(r.*f.member);
  for (const auto& [name, bytes] : r.held_bytes) o << " held." << pct_encode(name) << '=' << fmt_double(bytes);
  return o.str();
}

CellResult decode_result(const std::string& out) {
  std::map<std::string, const Field*> by_name;
  for (const Field& f : fields()) by_name[f.name] = &f;
  CellResult r;
  for (const auto& [k, v] : parse_result_line(out, "DBCELL")) {
    if (k == "status") r.status = v;
    else if (k == "message") r.message = v;
    else if (k == "ordering") r.ordering = v;
    else if (k.rfind("held.", 0) == 0) r.held_bytes.emplace_back(pct_decode(k.substr(5)), parse_double(v));
    else if (auto it = by_name.find(k); it != by_name.end()) r.*(it->second->member) = parse_double(v);
    // Unknown keys are ignored: a newer child talking to an older parent.
  }
  return r;
}

CellResult measure_cell(const CellSpec& spec) {
  CellResult r;
  const Mesh mesh = read_mesh(spec.mesh_path);
  validate_mesh(mesh);
  const Edit edit = make_thesis_edit(mesh, spec.edit);
  r.vertices = mesh.num_vertices();
  r.baseline_rss_bytes = static_cast<double>(current_rss_bytes());

  DeformOptions o;
  o.method = spec.system;
  o.constraints = ConstraintMode::Soft;  // thesis eq. 2-4: handle and anchors stay unknowns
  o.build = parse_build(spec.build);
  o.solver = spec.build == "dense" ? "" : spec.backend;  // the dense build's default dense backend (backend_label)
  o.solver_options.ordering = spec.ordering;
  o.solver_options.factor_dir = spec.factor_dir;
  o.memory_budget = spec.memory_budget_bytes;
  auto d = make_deformer(mesh, edit, o);

  std::vector<double> ft, rhs, solve, write;
  Points V;
  for (int f = 1; f <= spec.frames; ++f) {
    V = d->deform(interpolate_transform(edit.transform, static_cast<double>(f) / spec.frames));
    const PhaseTimes& t = d->times();
    ft.push_back(t.frame());
    rhs.push_back(t.rhs);
    solve.push_back(t.solve);
    write.push_back(t.write);
  }
  const PhaseTimes& t = d->times();
  const SystemReport& s = d->systems().front();
  r.n = static_cast<double>(s.n);
  r.nnz = static_cast<double>(s.nnz);
  r.nnz_factor = static_cast<double>(s.factor.nnz_factor);
  r.factor_flops = s.factor.flops;
  r.min_pivot_ratio = s.factor.min_pivot_ratio;
  r.ordering = s.factor.ordering_used;
  r.build_s = t.build;
  r.analyze_s = t.analyze;
  r.factorize_s = t.factorize;
  r.init_s = t.init();
  r.frames = spec.frames;
  r.frame_s = median(ft);
  r.rhs_s = median(rhs);
  r.solve_s = median(solve);
  r.write_s = median(write);
  r.fps = 1.0 / r.frame_s;
  r.matrix_bytes = static_cast<double>(d->matrix_bytes());
  r.factor_bytes = static_cast<double>(d->factor_bytes());
  double held = 0;
  for (const auto& [name, bytes] : s.held_bytes) {
    r.held_bytes.emplace_back(name, static_cast<double>(bytes));
    held += static_cast<double>(bytes);
  }
  r.held_total_bytes = held;
  r.mean_displacement = (V - mesh.V).rowwise().norm().mean() / bbox_diagonal(mesh.V);
  r.peak_rss_bytes = static_cast<double>(peak_rss_bytes());
  return r;
}

int cell_main(int argc, char** argv) {
  CellResult r;
  // The spec is parsed inside the guard: a malformed command line is an error result too.
  const CellOutcome o = run_guarded_cell([&] {
    const CellSpec spec = CellSpec::from_args(parse_args(argc, argv, 1, {"--cell"}));
    limit_address_space(spec.address_space_limit);
    r = measure_cell(spec);
  });
  if (o.status != "ok") {
    r.status = o.status;
    r.message = o.message;
  }
  if (std::isnan(r.peak_rss_bytes)) r.peak_rss_bytes = static_cast<double>(peak_rss_bytes());
  std::cout << '\n' << encode_result(r) << std::endl;
  return o.exit_code;
}

CellResult run_cell_in_child(const std::string& exe, const CellSpec& spec, double timeout_s) {
  ::malloc_trim(0);  // the forked image counts in the child's ru_maxrss: hand freed heap back first
  const double parent_rss = static_cast<double>(current_rss_bytes());
  std::vector<std::string> argv{exe};
  for (auto& a : spec.to_args()) argv.push_back(a);
  const ChildRun c = run_child(argv, timeout_s);
  CellResult r;
  bool decoded = false;
  try {
    r = decode_result(c.out);
    decoded = true;
  } catch (const std::exception&) {
  }
  if (!decoded || c.timed_out || c.term_signal) {
    // No trustworthy result line: the child crashed, was killed or was cut off.
    const double vmhwm = decoded ? r.peak_rss_bytes : kNaN;
    r = CellResult{};
    r.status = "error";
    r.message = fmt::format("child {}; stderr: {}", c.describe(), c.stderr_tail(400));
    r.peak_rss_bytes = vmhwm;
  }
  r.runs = 1;
  r.exit = c.describe();
  r.ru_maxrss_bytes = static_cast<double>(c.ru_maxrss_bytes);
  r.parent_rss_bytes = parent_rss;
  r.wall_s = c.wall_s;
  return r;
}

CellResult median_of(const std::vector<CellResult>& runs) {
  if (runs.empty()) throw Error("median_of: no runs");
  CellResult m = runs.front();
  for (const Field& f : fields()) {
    std::vector<double> v;
    for (const auto& r : runs)
      if (!std::isnan(r.*f.member)) v.push_back(r.*f.member);
    m.*f.member = v.empty() ? kNaN : median(v);
  }
  m.runs = static_cast<double>(runs.size());
  return m;
}

CellResult run_budgeted(const CellSpec& spec, const Prediction& p, double memory_budget_bytes, double time_budget_s,
                        const std::function<CellResult(const CellSpec&)>& runner) {
  CellResult r;
  if (memory_budget_bytes > 0 && p.total_bytes > memory_budget_bytes) {
    r.status = "#over";
    r.message = fmt::format("predicted {:.1f} MiB > memory budget {:.1f} MiB; not attempted", p.total_bytes / 1048576,
                            memory_budget_bytes / 1048576);
  } else if (time_budget_s > 0 && p.seconds > time_budget_s) {
    r.status = "#slow";
    r.message = fmt::format("predicted {:.3g} s > time budget {:.3g} s; not attempted", p.seconds, time_budget_s);
  } else {
    r = runner(spec);
  }
  r.predicted = p;
  return r;
}

}  // namespace db::harness
