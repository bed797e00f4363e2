// deformbench: command-line front end (`deformbench --help`; docs/cli.md).
//   deformbench deform <edit> --out FILE [options]   one edit, its phase times and bytes
//   deformbench solvers                              the linear-solver backends, with what each accepts
//   deformbench provenance                           what result rows record about this machine and build
//   deformbench deform-options                       the deform options as Markdown (docs/cli.md)
//   deformbench coat|transplant SOURCE TARGET --out FILE   the applications
//   deformbench export-system EDIT --out A.mtx [--rhs B.mtx]  an edit's linear system as Matrix Market files
// Each subcommand that does work has its file in apps/commands/.
//   mpirun -np N deformbench deform <edit> --solver mumps ...   one edit on N ranks (MUMPS distributed; rank 0
//                                                                prints and writes; the other subcommands refuse)
// Options are checked before any work: a value out of range, an option the chosen method or backend does not use,
// or an output that could not be written is a usage error (exit 1) before a mesh is read.
#include <iostream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "commands/commands.h"
#include "core/cli.h"
#include "solvers/base/error.h"
#include "core/provenance.h"
#include "edit/edit.h"
#include "solvers/linear_solver.h"
#include "solvers/mumps_mpi.h"

namespace {

using namespace db;

// One line a backend: its name first, then what the deform options may ask of it.
int cmd_solvers() {
  for (const std::string& s : solver_names()) {
    const SolverInfo info = solver_info(s);
    fmt::print("{:<24} {:<16} orderings {}{}\n", s, info.family, fmt::join(info.orderings, ","),
               info.out_of_core ? " | --factor-dir" : "");
  }
  return 0;
}

int cmd_provenance() {
  for (const auto& kv : provenance().columns()) std::cout << kv.first << ": " << kv.second << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("deformbench: linear mesh deformation (LAP, TF, LRI) with interchangeable linear solvers",
               "deformbench");
  app.require_subcommand(1);
  app.footer("Exit codes: 0 ok, 1 usage (an unknown option, a value out of range, options that do not go together, an "
             "output that cannot be written), 2 bad input (a mesh, an edit, a selection), 3 solver failure (singular, "
             "indefinite, non-finite), 4 over the memory budget; 128 + N when ended by signal N.");
  const commands::Command deform = commands::add_deform(app);
  CLI::App* solvers = app.add_subcommand("solvers", "list the linear-solver backends and the orderings each accepts");
  CLI::App* prov = app.add_subcommand("provenance", "print what result rows record about this machine and build");
  const std::vector<commands::Command> subcommands = {deform, commands::add_deform_options_listing(app),
                                                      commands::add_coat(app), commands::add_transplant(app),
                                                      commands::add_export_system(app), commands::add_advise(app)};
  const int code = cli::run(app, argc, argv, [&] {
    // Only deform runs on ranks; another subcommand would run once per rank, each writing the same output.
    if (!deform.app->parsed() && mpi::launched() && mpi::size() > 1)
      throw UsageError(fmt::format("started on {} ranks: only `deformbench deform --solver mumps` runs under mpirun; "
                                   "`{}` runs in one process (start it without mpirun)",
                                   mpi::size(), app.get_subcommands().front()->get_name()));
    for (const commands::Command& c : subcommands)
      if (c.app->parsed()) return c.run();
    if (solvers->parsed()) return cmd_solvers();
    if (prov->parsed()) return cmd_provenance();
    return 1;
  });
  // A failure on some ranks would leave the others waiting in a collective call: end them all with its code.
  if (code != 0 && mpi::launched() && mpi::size() > 1) mpi::abort_all(code);
  return code;
}
