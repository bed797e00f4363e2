// The assembly tree's parallelism under the multifrontal factorization's plan (issue 31, item 3: what limits the
// factorization beyond 8 threads). Per thread count T the plan (solvers/multifrontal/schedule.h) splits the tree
// into T groups of independent subtrees, factored at once with a single-threaded BLAS, and a top set of
// supernodes factored one after another with the BLAS's T threads. This driver counts, from the symbolic analysis
// alone, the flops each phase gets: they are the same on every machine, so the share the top phase takes at 16 or
// 64 threads is known on 2 cores. The vertex ordering is the one a run on T threads computes (METIS dissects one
// more level per doubling of the threads beyond two: solvers/ordering/graph_ordering.h), so the rows also give its
// fill per thread count. Per edit, system (tf: 3x3 blocks under METIS, lap: scalar under AMD, the structured
// builds' default vertex orderings) and T, one CSV row: nnz(L), supernodes, flops, the largest and mean group,
// the top set (supernodes, flops, share, the costliest chain of top supernodes, its fronts' rows median and
// largest), and two bounds on the factorization's speedup over one thread: `bound_top_serial` with the top phase
// on one core, `bound_top_ideal` with it at T times one core's rate (a BLAS that scales perfectly on those fronts).
// The solves' plan for T threads, balanced by factor entries (what a solve reads): its largest group and top in
// entries, and `solve_bound`, nnz(L) over their sum, the solve's speedup if each thread streamed at one core's
// rate (the solves take the top serially; shortest_plan in solvers/multifrontal/schedule.h picks by this path).
//
//   build/exp_tree_parallelism --edit data/edits/armadillo_loop1_whole.edit --threads 1,2,4,8,16,32,64
//       --csv results/tree_parallelism.csv
#include <cstdlib>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/cli.h"
#include "core/csv.h"
#include "core/provenance.h"
#include "edit/edit_io.h"
#include "methods/deformer.h"
#include "solvers/multifrontal/schedule.h"
#include "solvers/multifrontal/symbolic.h"
#include "systems/normal_system.h"
#include "systems/vertex_ordering.h"

namespace {

struct Options {
  std::vector<std::string> edits, systems{"tf", "lap"};
  std::vector<int> threads{1, 2, 4, 8, 16, 32, 64};
  std::string csv;
};

void define_options(CLI::App& app, Options& o) {
  app.add_option("--edit", o.edits, "an edit: a .edit file or a BS08 stem such as data/bs08/bar (repeatable)")
      ->required();
  app.add_option("--system", o.systems, "tf and/or lap (comma-separated)")->delimiter(',')
      ->check(db::cli::OneOf({"tf", "lap"}))->capture_default_str();
  app.add_option("--threads", o.threads, "thread counts (comma-separated, 1-64: the backend's range)")->delimiter(',')
      ->check(db::cli::Integer(1, 64))->capture_default_str();
  app.add_option("--csv", o.csv, "the rows, with provenance")->required();
}

//! The multifrontal backend's symbolic analysis of the edit's structured system, as a deformation on `threads`
//! threads runs it: the unknowns numbered in the default vertex ordering, the ordered matrix analyzed in its
//! natural order. DEFORMBENCH_THREADS (what worker_threads() reads) is set for the ordering and put back after it,
//! for the rows' provenance.
db::multifrontal::Symbolic symbolic(const db::EditCase& c, const db::Adjacency& adj, const std::string& system,
                                    int threads) {
  const int b = system == "tf" ? 3 : 1;
  const char* set = std::getenv("DEFORMBENCH_THREADS");
  const std::optional<std::string> was = set ? std::optional<std::string>(set) : std::nullopt;
  setenv("DEFORMBENCH_THREADS", std::to_string(threads).c_str(), 1);
  db::Unknowns unk = db::make_unknowns(db::classify(c.edit, db::ConstraintMode::Soft), 1.0);
  db::order_unknowns(adj, unk, db::default_vertex_ordering(b));
  if (was) setenv("DEFORMBENCH_THREADS", was->c_str(), 1);
  else unsetenv("DEFORMBENCH_THREADS");
  return db::multifrontal::analyze_blocks(db::expand_upper(db::interaction_pattern(adj, unk), b), b, "natural");
}

db::CsvTable::Row row(const db::EditCase& c, const std::string& system, const db::multifrontal::Symbolic& S,
                      const std::vector<double>& flops, const std::vector<double>& entries, int T) {
  const db::multifrontal::PlanCounts p = db::multifrontal::plan_counts(S, db::multifrontal::schedule(S, T, flops), flops);
  const db::multifrontal::PlanCounts q =
      db::multifrontal::plan_counts(S, db::multifrontal::schedule(S, T, entries), entries);
  return {{"edit", c.edit.name},
          {"vertices", std::to_string(c.mesh.V.rows())},
          {"system", system},
          {"threads", std::to_string(T)},
          {"nnz_L", std::to_string(S.nnz)},
          {"supernodes", std::to_string(S.nsuper())},
          {"flops", db::num(S.flops)},
          {"group_flops_max", db::num(p.group_max)},
          {"group_flops_mean", db::num(p.group_mean)},
          {"top_supernodes", std::to_string(p.top_supernodes)},
          {"top_flops", db::num(p.top)},
          {"top_share", db::num(p.top / S.flops)},
          {"top_path_flops", db::num(p.top_path)},
          {"top_rows_median", std::to_string(p.top_rows_median)},
          {"top_rows_max", std::to_string(p.top_rows_max)},
          {"bound_top_serial", db::num(S.flops / (p.group_max + p.top))},
          {"bound_top_ideal", db::num(S.flops / (p.group_max + p.top / T))},
          {"solve_group_entries_max", db::num(q.group_max)},
          {"solve_top_entries", db::num(q.top)},
          {"solve_bound", db::num(double(S.nnz) / (q.group_max + q.top))}};
}

int run(const Options& o) {
  db::cli::check_output("--csv", o.csv, {".csv"}, o.edits);
  db::CsvTable table;
  for (const std::string& e : o.edits) {
    const db::EditCase c = db::load_edit_case(e);
    const db::Adjacency adj = db::vertex_adjacency(c.mesh);
    for (const std::string& system : o.systems)
      for (int T : o.threads) {
        const db::multifrontal::Symbolic S = symbolic(c, adj, system, T);
        std::vector<double> flops(std::size_t(S.nsuper()));
        std::vector<double> entries(std::size_t(S.nsuper()));
        for (int s = 0; s < S.nsuper(); ++s) {
          flops[std::size_t(s)] = db::multifrontal::supernode_flops(S, s);
          entries[std::size_t(s)] = double(S.xptr[std::size_t(s) + 1] - S.xptr[std::size_t(s)]);
        }
        table.add(row(c, system, S, flops, entries, T));
        std::cout << fmt::format("{} {} T={}: nnz(L) {}, {} supernodes, {:.4g} flops\n", c.edit.name, system, T, S.nnz,
                                 S.nsuper(), S.flops);
      }
  }
  table.write(o.csv);
  std::cout << "wrote " << o.csv << " | " << db::provenance_summary() << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Per thread count, the fill of the vertex ordering a run computes and what the multifrontal "
               "factorization's plan gives its subtree groups and its serial top phase (counts, no timing).",
               "exp_tree_parallelism");
  Options o;
  define_options(app, o);
  return db::cli::run(app, argc, argv, [&] { return run(o); });
}
