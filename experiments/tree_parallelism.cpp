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
//
//   build/exp_tree_parallelism --edit data/edits/armadillo_loop1_whole.edit --threads 1,2,4,8,16,32,64
//       --csv results/tree_parallelism.csv
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/csv.h"
#include "core/csv_reader.h"
#include "core/provenance.h"
#include "edit/edit_io.h"
#include "methods/deformer.h"
#include "solvers/base/error.h"
#include "solvers/multifrontal/schedule.h"
#include "solvers/multifrontal/symbolic.h"
#include "systems/normal_system.h"
#include "systems/vertex_ordering.h"

namespace {

struct Args {
  std::vector<std::string> edits, systems{"tf", "lap"};
  std::vector<int> threads{1, 2, 4, 8, 16, 32, 64};
  std::string csv;
};

Args parse(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string key = argv[i];
    if (i + 1 >= argc) throw db::UsageError(key + " needs a value");
    const std::string value = argv[++i];
    if (key == "--edit") a.edits.push_back(value);
    else if (key == "--system") a.systems = db::split_csv_line(value);
    else if (key == "--csv") a.csv = value;
    else if (key == "--threads") {
      a.threads.clear();
      for (const std::string& t : db::split_csv_line(value)) a.threads.push_back(std::stoi(t));
    } else throw db::UsageError("unknown option " + key + " (expected --edit, --system, --threads, --csv)");
  }
  for (int t : a.threads)
    if (t < 1 || t > 64) throw db::UsageError(fmt::format("--threads: {} is not in 1..64 (the backend's range)", t));
  if (a.edits.empty() || a.csv.empty())
    throw db::UsageError("usage: exp_tree_parallelism --edit E [--edit E2] [--system tf,lap] [--threads 1,2,..] --csv OUT");
  return a;
}

//! The multifrontal backend's symbolic analysis of the edit's structured system, as a deformation on `threads`
//! threads runs it: the unknowns numbered in the default vertex ordering, the ordered matrix analyzed in its
//! natural order.
db::multifrontal::Symbolic symbolic(const db::EditCase& c, const std::string& system, int threads) {
  const int b = system == "tf" ? 3 : 1;
  // worker_threads() reads the variable; it is put back afterwards, for the rows' provenance.
  const char* was = std::getenv("DEFORMBENCH_THREADS");
  const std::string saved = was ? was : "";
  setenv("DEFORMBENCH_THREADS", std::to_string(threads).c_str(), 1);
  struct Restore {
    const char* was;
    const std::string& saved;
    ~Restore() { was ? setenv("DEFORMBENCH_THREADS", saved.c_str(), 1) : unsetenv("DEFORMBENCH_THREADS"); }
  } restore{was, saved};
  const db::Adjacency adj = db::vertex_adjacency(c.mesh);
  db::Unknowns unk = db::make_unknowns(db::classify(c.edit, db::ConstraintMode::Soft), 1.0);
  db::order_unknowns(adj, unk, db::default_vertex_ordering(b));
  return db::multifrontal::analyze_blocks(db::expand_upper(db::interaction_pattern(adj, unk), b), b, "natural");
}

db::CsvTable::Row row(const db::EditCase& c, const std::string& system, const db::multifrontal::Symbolic& S,
                      const std::vector<double>& flops, int T) {
  const db::multifrontal::PlanCounts p = db::multifrontal::plan_counts(S, db::multifrontal::schedule(S, T, flops), flops);
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
          {"bound_top_ideal", db::num(S.flops / (p.group_max + p.top / T))}};
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Args a = parse(argc, argv);
    db::CsvTable table;
    for (const std::string& e : a.edits) {
      const db::EditCase c = db::load_edit_case(e);
      for (const std::string& system : a.systems) {
        if (system != "tf" && system != "lap") throw db::UsageError("--system: " + system + " is not tf or lap");
        for (int T : a.threads) {
          const db::multifrontal::Symbolic S = symbolic(c, system, T);
          std::vector<double> flops(std::size_t(S.nsuper()));
          for (int s = 0; s < S.nsuper(); ++s) flops[std::size_t(s)] = db::multifrontal::supernode_flops(S, s);
          table.add(row(c, system, S, flops, T));
          std::cout << fmt::format("{} {} T={}: nnz(L) {}, {} supernodes, {:.4g} flops\n", c.edit.name, system, T, S.nnz,
                                   S.nsuper(), S.flops);
        }
      }
    }
    table.write(a.csv);
    std::cout << "wrote " << a.csv << " | " << db::provenance_summary() << "\n";
    return 0;
  } catch (const db::UsageError& e) {
    std::cerr << "exp_tree_parallelism: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "exp_tree_parallelism: " << e.what() << "\n";
    return 2;
  }
}
