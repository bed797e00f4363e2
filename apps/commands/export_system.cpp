// deformbench export-system EDIT --out A.mtx [--rhs B.mtx] [--least-squares] [--system NAME] [method options]:
// the linear system of one edit as Matrix Market files, for other solver developers and for `exp_solvers
// --matrix`. The system is the deformer's (methods/edit_system.h: structured build, the mesh's vertex order,
// normalized coordinates); the method, constraint and weight options are the deform options' table's
// (methods/deform_option_flags.h). Files are staged and land together or not at all (solvers/base/atomic_file.h).
#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "commands.h"
#include "core/cli.h"
#include "core/provenance.h"
#include "edit/edit_io.h"
#include "methods/deform_option_flags.h"
#include "methods/edit_system.h"
#include "solvers/base/atomic_file.h"
#include "solvers/base/error.h"
#include "systems/matrix_market.h"

namespace db::commands {
namespace {

struct ExportArgs {
  std::string edit, out, rhs, system;
  bool least_squares = false;
  DeformOptionValues values;
};

void add_export_options(CLI::App& e, ExportArgs& a) {
  e.add_option("edit", a.edit, "a Botsch-Sorkine stem (STEM.off|.ply|.obj + STEM.sel + STEM.def) or a .edit file")
      ->type_name("EDIT")->required();
  e.add_option("--out", a.out, "the matrix (.mtx): the normal matrix K as 'coordinate real symmetric' (its lower "
               "triangle), or with --least-squares the rectangular A as 'coordinate real general'")
      ->type_name("FILE")->required();
  e.add_option("--rhs", a.rhs, "also the right-hand side of the edit's full drag (.mtx, 'array real general', one "
               "column per coordinate; lap and tf)")
      ->type_name("FILE");
  e.add_flag("--least-squares", a.least_squares, "A and b of min ||A x - b|| (A^T A = K) instead of K (lap, tf)");
  e.add_option("--system", a.system, "lri: which of its systems, frames or positions (default frames)")
      ->check(cli::OneOf({"frames", "positions"}));
  add_deform_option_flags(e, a.values, system_option_groups());
}

// What a file's comment lines say: where it came from.
std::string provenance_comment(const ExportArgs& a, const DeformOptions& o, const std::string& what) {
  std::string opts;
  const std::vector<std::string>& groups = system_option_groups();
  for (const auto& [k, v] : deform_option_items(o))
    if (k != "method" && std::count(groups.begin(), groups.end(), deform_option_def(k).group) > 0)
      opts += fmt::format(" {}={}", k, v);
  return fmt::format("deformbench export-system: {} of edit {} (method {}{}; structured build, vertex order of the "
                     "mesh, normalized coordinates)\n{}",
                     what, a.edit, to_string(o.method), opts, provenance_summary());
}

void check_args(const CLI::App& e, const ExportArgs& a, const DeformOptions& o) {
  const bool lri = o.method == Method::Lri;
  if (lri && a.least_squares) throw UsageError("--least-squares: lap and tf only (lri's systems are solved in turn)");
  if (lri && e.count("--rhs") > 0)
    throw UsageError("--rhs: lap and tf only (lri's right-hand sides follow from each frame's frame solve)");
  if (!lri && e.count("--system") > 0)
    throw UsageError(fmt::format("--system chooses between lri's two systems; --method {} has one", to_string(o.method)));
  const std::vector<std::string> inputs = edit_case_files(a.edit);
  cli::check_output("--out", a.out, {".mtx"}, inputs);
  if (e.count("--rhs") > 0) cli::check_output("--rhs", a.rhs, {".mtx"}, inputs);
  if (e.count("--rhs") > 0 && same_file(a.out, a.rhs))
    throw UsageError(fmt::format("--out {} and --rhs {} name the same file", a.out, a.rhs));
}

int run_export(const CLI::App& e, ExportArgs& a) {
  const DeformOptions o = deform_options_given(e, a.values);
  check_args(e, a, o);
  const EditCase ec = load_edit_case(a.edit);
  StagedOutputs outputs;
  if (a.least_squares) {
    const LeastSquaresSystem ls = edit_least_squares(ec.mesh, ec.edit, o);
    write_atomically(outputs.stage(a.out),
                     [&](std::ostream& s) { write_market_general(s, ls.A, provenance_comment(a, o, "least-squares A")); });
    if (!a.rhs.empty())
      write_atomically(outputs.stage(a.rhs),
                       [&](std::ostream& s) { write_market_array(s, ls.b, provenance_comment(a, o, "least-squares b")); });
    outputs.commit();
    fmt::print("wrote {}: A {} x {}, {} entries{}\n", a.out, ls.A.rows(), ls.A.cols(), ls.A.nonZeros(),
               a.rhs.empty() ? "" : fmt::format("; {}: b {} x {}", a.rhs, ls.b.rows(), ls.b.cols()));
    return 0;
  }
  const std::vector<EditSystem> systems = edit_systems(ec.mesh, ec.edit, o);
  const EditSystem& sys = systems[a.system == "positions" ? 1 : 0];
  const std::string what = fmt::format("{} K (unknowns in blocks of {})", sys.name, sys.block);
  write_atomically(outputs.stage(a.out),
                   [&](std::ostream& s) { write_market_symmetric(s, sys.K, provenance_comment(a, o, what)); });
  if (!a.rhs.empty())
    write_atomically(outputs.stage(a.rhs), [&](std::ostream& s) {
      write_market_array(s, sys.rhs, provenance_comment(a, o, sys.name + " right-hand side"));
    });
  outputs.commit();
  fmt::print("wrote {}: system {} (block {}: exp_solvers --matrix-block {}), n {}, {} entries in its lower triangle{}\n",
             a.out, sys.name, sys.block, sys.block,
             sys.K.rows(), sys.K.nonZeros(),
             a.rhs.empty() ? "" : fmt::format("; {}: {} x {}", a.rhs, sys.rhs.rows(), sys.rhs.cols()));
  return 0;
}

}  // namespace

Command add_export_system(CLI::App& tool) {
  auto a = std::make_shared<ExportArgs>();
  CLI::App* app = tool.add_subcommand("export-system", "write an edit's linear system as Matrix Market files");
  add_export_options(*app, *a);
  return {app, [app, a] { return run_export(*app, *a); }};
}

}  // namespace db::commands
