// The analysis phase of the structured LAP / TF systems under several vertex orderings, in interleaved rounds
// (a shared machine drifts: each round runs every ordering once, so ratios within a round compare like with
// like). Per edit, system, ordering and round one CSV row: the vertex ordering's wall time (order_s), this
// process's CPU time in it, all threads (order_cpu_s), and its children's (order_children_cpu_s: builds before
// the per-thread METIS draws of solvers/ordering/metis_random.h ordered one side of a split in a forked child;
// 0 since), the
// multifrontal backend's symbolic analysis of the ordered system (mf_analyze_s; with the natural ordering and the
// ordering's elimination tree where it found one, as the deformation hands them), their sum (analysis_s, the
// deformation's "analyze" phase) and the factor's nnz(L) and flops. Where the ordering handed a tree
// (tree_given 1), the same analysis without it (mf_own_tree_s: CHOLMOD's own pass over the graph) is timed too,
// before or after the other in alternate rounds; without a tree (tree_given 0: one thread, or an ordering that is
// not a dissected METIS one) mf_own_tree_s repeats mf_analyze_s. Soft constraints, as the solver study's systems.
//
//   build/exp_analysis --edit data/edits/armadillo_loop1_whole.edit --system tf --orderings metis,ringnd
//       --rounds 5 --csv results/analysis.csv
#include <cstdlib>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <sys/resource.h>

#include <fmt/format.h>

#include "core/cli.h"
#include "core/csv.h"
#include "core/provenance.h"
#include "core/timer.h"
#include "edit/edit_io.h"
#include "methods/deformer.h"
#include "solvers/base/error.h"
#include "solvers/base/resources.h"
#include "solvers/linear_solver.h"
#include "systems/normal_system.h"
#include "systems/vertex_ordering.h"

namespace {

struct Args {
  std::vector<std::string> edits, systems{"tf"}, orderings{"metis", "ringnd"};
  int rounds = 3;
  std::string csv;
};

void define_options(CLI::App& app, Args& a) {
  app.add_option("--edit", a.edits, "an edit: a .edit file or a BS08 stem (repeatable)")->required();
  app.add_option("--system", a.systems, "tf and/or lap (comma-separated)")->delimiter(',')
      ->check(db::cli::OneOf({"tf", "lap"}))->capture_default_str();
  app.add_option("--orderings", a.orderings, "vertex orderings (comma-separated)")->delimiter(',')
      ->capture_default_str();
  app.add_option("--rounds", a.rounds, "rounds, each running every ordering once")->check(db::cli::Integer(1, 1000))
      ->capture_default_str();
  app.add_option("--csv", a.csv, "the rows, with provenance")->required();
}

//! The value of column `key` in `row`.
std::string value(const db::CsvTable::Row& row, const std::string& key) {
  for (const auto& [k, v] : row)
    if (k == key) return v;
  return {};
}

//! CPU seconds (user and system) of this process's children that have been waited for.
double children_cpu_seconds() {
  rusage r{};
  getrusage(RUSAGE_CHILDREN, &r);
  return double(r.ru_utime.tv_sec + r.ru_stime.tv_sec) + 1e-6 * double(r.ru_utime.tv_usec + r.ru_stime.tv_usec);
}

//! One edit's unknowns before any ordering.
struct Case {
  db::EditCase edit;
  db::Adjacency adj;
  db::Unknowns unk;
};

//! Orders, analyzes and measures one cell; one CSV row.
db::CsvTable::Row measure(const Case& c, const std::string& system, const std::string& ordering, int round) {
  const int b = system == "tf" ? 3 : 1;
  db::Unknowns unk = c.unk;
  db::Timer t;
  const db::CpuTimer cpu;
  const double children0 = children_cpu_seconds();
  db::order_unknowns(c.adj, unk, ordering);
  const double order_s = t.seconds(), order_cpu_s = cpu.seconds(), children_s = children_cpu_seconds() - children0;
  const db::SpMat K = db::expand_upper(db::interaction_pattern(c.adj, unk), b);  // the ordered system's pattern
  const auto analyze = [&](std::shared_ptr<const db::EliminationTree> tree, db::FactorStats* st) {
    db::SolverOptions so;
    so.ordering = "natural";
    so.block_size = b;
    so.elimination_tree = std::move(tree);
    const auto solver = db::make_solver("multifrontal", so);
    db::Timer at;
    solver->analyze(K);
    const double s = at.seconds();
    if (st) *st = solver->stats();
    return s;
  };
  db::FactorStats st;
  const double own_first = unk.tree && round % 2 == 1 ? analyze(nullptr, nullptr) : 0;
  const double analyze_s = analyze(unk.tree, &st);
  const double own_s = !unk.tree ? analyze_s : round % 2 == 1 ? own_first : analyze(nullptr, nullptr);
  return {{"edit", c.edit.edit.name},
          {"vertices", std::to_string(c.edit.mesh.V.rows())},
          {"system", system},
          {"ordering", ordering},
          {"round", std::to_string(round)},
          {"order_s", db::num(order_s)},
          {"order_cpu_s", db::num(order_cpu_s)},
          {"order_children_cpu_s", db::num(children_s)},
          {"mf_analyze_s", db::num(analyze_s)},
          {"tree_given", unk.tree ? "1" : "0"},
          {"mf_own_tree_s", db::num(own_s)},
          {"analysis_s", db::num(order_s + analyze_s)},
          {"nnz_L", std::to_string(st.nnz_factor)},
          {"gflop", db::num(st.flops / 1e9)},
          {"threads", std::to_string(db::worker_threads())}};
}

int run(const Args& a) {
  db::cli::check_output("--csv", a.csv, {".csv"}, a.edits);
  std::vector<Case> cases;
  for (const std::string& e : a.edits) {
    Case c{db::load_edit_case(e), {}, {}};
    c.adj = db::vertex_adjacency(c.edit.mesh);
    c.unk = db::make_unknowns(db::classify(c.edit.edit, db::ConstraintMode::Soft), 1.0);
    cases.push_back(std::move(c));
  }
  db::CsvTable table;
  for (int r = 0; r < a.rounds; ++r)
    for (const Case& c : cases)
      for (const std::string& s : a.systems)
        for (const std::string& o : a.orderings) {
          db::CsvTable::Row row = measure(c, s, o, r);
          std::cout << fmt::format("round {} {} {} {}: analysis {} s, nnz(L) {}\n", r, c.edit.edit.name, s, o,
                                   value(row, "analysis_s"), value(row, "nnz_L"))
                    << std::flush;
          table.add(std::move(row));
        }
  table.write(a.csv);
  std::cout << "wrote " << a.csv << " | " << db::provenance_summary() << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("The analysis phase (vertex ordering + symbolic analysis) of the structured systems per vertex "
               "ordering, in interleaved rounds.",
               "exp_analysis");
  Args a;
  define_options(app, a);
  return db::cli::run(app, argc, argv, [&] { return run(a); });
}
