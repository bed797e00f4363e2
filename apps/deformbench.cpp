// deformbench: command-line front end.
//   deformbench deform <edit> --method lap|tf --out result.ply [options]
//   deformbench solvers            list the linear solver backends
//   deformbench provenance         print what result rows record about this machine and build
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/args.h"
#include "core/csv.h"
#include "core/error.h"
#include "core/provenance.h"
#include "core/resources.h"
#include "edit/edit_io.h"
#include "edit/transform.h"
#include "harness/stats.h"
#include "mesh/mesh_io.h"
#include "methods/deformer.h"
#include "methods/drag.h"

namespace {

const char* kUsage = R"(usage:
  deformbench deform <edit> --out FILE [options]
      <edit>: a BS08 stem (STEM.off + STEM.sel + STEM.def) or a .edit file
      --method lap|tf|lri        method (default lap)
      --weights uniform|cotan    Laplacian weights (default uniform)
      --constraints hard|soft    eliminate handle/fixed vertices or weight them (default hard)
      --soft-weight W            weight of soft constraint rows (default 1)
      --tf-no-translation        TF without the translation fit (thesis eq. 2-12)
      --lri-frames first|random|height_angle|curvature   LRI local frame strategy (default first)
      --lri-orthonormalize gram_schmidt|polar            LRI frame orthonormalization (default gram_schmidt)
      --lri-seed N               seed of the random frame strategy
      --build structured|naive|dense   how the normal matrix is formed (default structured)
      --solver NAME              linear solver backend (default multifrontal; see `deformbench solvers`)
      --ordering amd|metis|nesdis|natural|default
      --factor-dir DIR           out of core: keep the factor in a scratch file in DIR (multifrontal only)
      --no-normalize             build in raw coordinates (for diagnosis; TF may fail)
      --transform SPEC           override the edit's handle transform (translate:x,y,z | rotate:DEG:ax,ay,az[:px,py,pz] | matrix:...)
      --frames N                 interpolate the transform over N frames, report the median frame time (default 1)
      --memory-budget-mb MB      refuse builds predicted above this
      --csv FILE                 append-free: write one tidy CSV row (atomically) with the measurements
  deformbench solvers
  deformbench provenance
exit codes: 0 ok, 1 usage or other error, 2 bad input, 3 solver failure, 4 over budget)";

int cmd_deform(const db::Args& a) {
  if (a.positional.size() != 1) throw db::Error("deform takes exactly one <edit>");
  if (!a.has("--out")) throw db::Error("deform needs --out FILE");
  const std::string out = a.get("--out", "");
  // Fail before the (possibly long) solve when the result could not be written anyway.
  const auto out_dir = std::filesystem::path(out).parent_path();
  if (!out_dir.empty() && !std::filesystem::is_directory(out_dir))
    throw db::Error("output directory does not exist: " + out_dir.string());
  db::DeformOptions o;
  o.method = a.get("--method", "lap");
  o.weights = db::parse_weights(a.get("--weights", "uniform"));
  o.constraints = db::parse_constraints(a.get("--constraints", "hard"));
  o.soft_weight = a.number("--soft-weight", 1.0);
  o.tf_translation = !a.has("--tf-no-translation");
  o.lri_frames = a.get("--lri-frames", o.lri_frames);
  o.lri_orthonormalize = a.get("--lri-orthonormalize", o.lri_orthonormalize);
  o.lri_seed = static_cast<unsigned>(a.number("--lri-seed", o.lri_seed));
  o.build = db::parse_build(a.get("--build", "structured"));
  o.solver = a.get("--solver", "multifrontal");
  o.solver_options.ordering = a.get("--ordering", "default");
  o.solver_options.factor_dir = a.get("--factor-dir", "");
  o.normalize = !a.has("--no-normalize");
  if (a.has("--memory-budget-mb"))
    o.memory_budget = static_cast<std::size_t>(a.number("--memory-budget-mb", 0) * 1e6);
  const int frames = static_cast<int>(a.number("--frames", 1));
  if (frames < 1) throw db::Error("--frames must be at least 1");

  db::EditCase ec = db::load_edit_case(a.positional[0]);
  if (a.has("--transform")) ec.edit.transform = db::parse_transform(a.get("--transform", ""));
  auto deformer = db::make_deformer(ec.mesh, ec.edit, o);

  std::vector<double> frame_times, rhs_times, solve_times, write_times;
  db::Points result;
  for (int f = 1; f <= frames; ++f) {
    result = deformer->deform(db::interpolate_transform(ec.edit.transform, static_cast<double>(f) / frames));
    const auto& ft = deformer->times();
    frame_times.push_back(ft.frame());
    rhs_times.push_back(ft.rhs);
    solve_times.push_back(ft.solve);
    write_times.push_back(ft.write);
  }
  const double median_frame = db::harness::median(frame_times);

  db::Mesh outm = ec.mesh;
  outm.V = result;
  db::write_mesh(out, outm);

  const auto& t = deformer->times();
  const auto& sys = deformer->systems().front();
  fmt::print("mesh {} ({} vertices, {} faces), edit {}: {} fixed, {} free, {} handle\n", ec.mesh.name,
             ec.mesh.num_vertices(), ec.mesh.num_faces(), ec.edit.name, ec.edit.count(db::Role::Fixed),
             ec.edit.count(db::Role::Free), ec.edit.count(db::Role::Handle));
  fmt::print("method {} | build {} | solver {} | constraints {}\n", o.method, db::to_string(o.build), o.solver,
             db::to_string(o.constraints));
  for (const auto& s : deformer->systems())
    fmt::print("  system {}: n {} | nnz {} | ordering {} | matrix {:.2f} MB | factor {:.2f} MB{} (nnz(L) {}, {:.2f} GFlop) "
               "| min pivot/diagonal {:.3g}\n",
               s.name, s.n, s.nnz, s.factor.ordering_used, s.matrix_bytes / 1e6, s.factor.factor_bytes / 1e6,
               s.factor.factor_on_disk ? " on disk" : "", s.factor.nnz_factor, s.factor.flops / 1e9,
               s.factor.min_pivot_ratio);
  for (const auto& s : deformer->systems())
    if (s.factor.min_pivot_ratio > 0 && s.factor.min_pivot_ratio < db::singular_pivot_bound(s.n))
      fmt::print("  note: system {} is ill-conditioned: its smallest pivot is {:.2g} of its diagonal entry, under the "
                 "{:.2g} (10 n eps) a singular matrix's rounding noise reaches; the constraints pin its null space, so "
                 "it is solved, but expect fewer correct digits\n",
                 s.name, s.factor.min_pivot_ratio, db::singular_pivot_bound(s.n));
  fmt::print("build {:.4f} s | analyze {:.4f} s | factorize {:.4f} s | init {:.4f} s\n", t.build, t.analyze,
             t.factorize, t.init());
  fmt::print("per frame (median of {}): {:.5f} s (medians: rhs {:.5f}, solve {:.5f}, write {:.5f})\n", frames,
             median_frame, db::harness::median(rhs_times), db::harness::median(solve_times),
             db::harness::median(write_times));
  double flops = 0;
  for (const auto& s : deformer->systems()) flops += s.factor.flops;
  fmt::print("matrix {:.2f} MB | factor {:.2f} MB ({:.1f} GFlop/s in factorize) | peak RSS {:.1f} MB\n",
             deformer->matrix_bytes() / 1e6, deformer->factor_bytes() / 1e6,
             t.factorize > 0 ? flops / 1e9 / t.factorize : 0.0, db::peak_rss_bytes() / 1e6);
  fmt::print("{}\n", db::provenance_summary());
  fmt::print("wrote {}\n", out);

  if (a.has("--csv")) {
    db::CsvTable csv;
    csv.add({{"mesh", ec.mesh.name},
             {"edit", ec.edit.name},
             {"vertices", std::to_string(ec.mesh.num_vertices())},
             {"faces", std::to_string(ec.mesh.num_faces())},
             {"handle", std::to_string(ec.edit.count(db::Role::Handle))},
             {"fixed", std::to_string(ec.edit.count(db::Role::Fixed))},
             {"method", o.method},
             {"weights", db::to_string(o.weights)},
             {"constraints", db::to_string(o.constraints)},
             {"build", db::to_string(o.build)},
             {"backend", o.solver},
             {"ordering", sys.factor.ordering_used},
             {"factor_storage", sys.factor.factor_on_disk ? "disk" : "memory"},
             {"n", std::to_string(sys.n)},
             {"nnz", std::to_string(sys.nnz)},
             {"nnz_factor", std::to_string(sys.factor.nnz_factor)},
             {"build_s", db::num(t.build)},
             {"analyze_s", db::num(t.analyze)},
             {"factorize_s", db::num(t.factorize)},
             {"init_s", db::num(t.init())},
             {"frames", std::to_string(frames)},
             {"frame_median_s", db::num(median_frame)},
             {"matrix_bytes", std::to_string(deformer->matrix_bytes())},
             {"factor_bytes", std::to_string(deformer->factor_bytes())},
             {"peak_rss_bytes", std::to_string(db::peak_rss_bytes())}});
    csv.write(a.get("--csv", ""));
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || !std::strcmp(argv[1], "-h") || !std::strcmp(argv[1], "--help")) {
    std::cout << kUsage << "\n";
    return argc < 2 ? 1 : 0;
  }
  const std::string cmd = argv[1];
  try {
    const db::Args a = db::parse_args(argc, argv, 2, {"--tf-no-translation", "--no-normalize"});
    if (cmd == "deform") return cmd_deform(a);
    if (cmd == "solvers") {
      for (const auto& s : db::solver_names()) std::cout << s << "\n";
      return 0;
    }
    if (cmd == "provenance") {
      for (const auto& kv : db::provenance().columns()) std::cout << kv.first << ": " << kv.second << "\n";
      return 0;
    }
    std::cerr << "deformbench: unknown command '" << cmd << "'\n" << kUsage << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "deformbench: error: " << e.what() << "\n";
    return db::exit_code(e);
  }
}
