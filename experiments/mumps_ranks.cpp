// MUMPS on N ranks against one process: the solver study's system (the thesis edit, soft constraints, structured
// build; harness/solver_cell.h) of one mesh, factored and solved by DistributedMumps on every rank of
// MPI_COMM_WORLD, or by one registry backend in this process for comparison. Run under a launcher:
//
//   scripts/mpirun.sh 2 build/exp_mumps_ranks --mesh data/generated/armadillo_loop1.off --csv r2.csv
//   build/exp_mumps_ranks --mesh data/generated/armadillo_loop1.off --solver multifrontal --csv mf.csv
//   scripts/mpirun.sh 8 build/exp_mumps_ranks --mesh M.off --analysis-only --input root --csv a8.csv
//   scripts/mpirun.sh 8 build/exp_mumps_ranks --mesh M.off --analysis-only --input centralized --csv a8.csv
//
// Input: `split` (default): every rank builds K and passes only its share of the columns (MUMPS's distributed
// assembled input, ICNTL(18)=3), then drops the rest; `root`: rank 0 builds and passes every entry (the others
// build nothing: for analysis-only estimates of systems too large to build N times on one machine; MUMPS's
// estimates depend on the number of ranks, not on who passed the entries); `centralized` (--analysis-only):
// rank 0 builds K's pattern alone, no value (harness/solver_cell.h, build_thesis_pattern), and passes it as
// MUMPS's centralized input (ICNTL(18)=0); the others build nothing: the estimates of systems whose values would
// not fit on the machine. --analysis-only stops after MUMPS's analysis: its estimates per
// rank (INFO(3), (15), (17)) and overall (INFOG(3), (16), (17), (26), (27), RINFOG(1)); `built_ranks` counts
// the ranks that built the system or its pattern.
// Rank 0 writes one CSV row with provenance, every rank's peak RSS gathered; --positions / --compare keep a
// solution and compare another with it (the largest coordinate difference, in units of the bounding-box
// diagonal: the system is built in normalized coordinates).
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/cli.h"
#include "core/csv.h"
#include "solvers/base/error.h"
#include "core/provenance.h"
#include "solvers/base/resources.h"
#include "core/timer.h"
#include "harness/positions.h"
#include "harness/solver_cell.h"
#include "solvers/linear_solver.h"
#include "solvers/mumps_distributed.h"
#include "solvers/mumps_mpi.h"

namespace {

using namespace db;
using namespace db::harness;

struct Options {
  std::string mesh, system = "tf", solver = "distributed", ordering = "default", input = "split";
  std::string csv, positions, compare, factor_dir, label;
  bool analysis_only = false;
};

void define_options(CLI::App& app, Options& o) {
  app.add_option("--mesh", o.mesh, "the mesh (.off/.ply/.obj); the thesis edit is made on it")->required()
      ->check(CLI::ExistingFile);
  app.add_option("--system", o.system, "lap or tf")->check(cli::OneOf({"lap", "tf"}))->capture_default_str();
  app.add_option("--solver", o.solver, "distributed (MUMPS on every rank) or a registry backend (one process)")
      ->capture_default_str();
  app.add_option("--ordering", o.ordering, "the solver's ordering (distributed: MUMPS's own or natural)")
      ->capture_default_str();
  app.add_option("--input", o.input,
                 "split (every rank passes its columns), root (rank 0 passes all) or centralized (rank 0 builds "
                 "the pattern alone and passes it as MUMPS's centralized input; with --analysis-only)")
      ->check(cli::OneOf({"split", "root", "centralized"}))->capture_default_str();
  app.add_flag("--analysis-only", o.analysis_only, "stop after the analysis (MUMPS's estimates)");
  app.add_option("--factor-dir", o.factor_dir, "out of core: the factor's files go here");
  app.add_option("--csv", o.csv, "one row of the measurements with provenance (written by rank 0)");
  app.add_option("--positions", o.positions, "write the solution here (binary, rank 0)");
  app.add_option("--compare", o.compare, "a solution written by --positions: report the largest difference");
  app.add_option("--label", o.label, "a name for the row (default: the mesh's file name)");
}

struct Row {
  CsvTable::Row cols;
  void add(const std::string& k, double v) { cols.emplace_back(k, num(v)); }
  void add(const std::string& k, const std::string& v) { cols.emplace_back(k, v); }
};

// Rank r's share of the upper triangle: columns [r n / N, (r+1) n / N) (every column, or none, with --input root).
// The values are left out when `vals` is null (an analysis needs the pattern only).
void my_entries(const SpMat& K, bool all, std::vector<int>& rows, std::vector<int>& cols, std::vector<double>* vals) {
  const long long n = K.cols(), r = mpi::rank(), N = mpi::size();
  const long long c0 = all ? 0 : r * n / N, c1 = all ? n : (r + 1) * n / N;
  for (long long c = c0; c < c1; ++c)
    for (SpMat::InnerIterator it(K, Index(c)); it; ++it) {
      rows.push_back(int(it.row()));
      cols.push_back(int(c));
      if (vals) vals->push_back(it.value());
    }
}

// K's upper-triangle entries from its block pattern, as expand_upper lays them out (reserved exactly: on the
// largest meshes they are most of rank 0's memory).
void pattern_entries(const ThesisPattern& t, std::vector<int>& rows, std::vector<int>& cols) {
  const InteractionPattern& p = t.pattern;
  const int b = t.block, nu = int(p.colptr.size()) - 1;
  rows.reserve(std::size_t(t.nnz_upper()));
  cols.reserve(std::size_t(t.nnz_upper()));
  for (int k = 0; k < nu; ++k)
    for (int c2 = 0; c2 < b; ++c2)
      for (int q = p.colptr[k]; q < p.colptr[k + 1]; ++q) {
        const int j = p.rows[std::size_t(q)];
        for (int c1 = 0; c1 < (j == k ? c2 + 1 : b); ++c1) {
          rows.push_back(b * j + c1);
          cols.push_back(b * k + c2);
        }
      }
}

void add_report(Row& row, const mumps::Report& m) {
  row.add("flops_estimated", m.flops_estimated);
  row.add("factor_entries_estimated", m.factor_entries_estimated);
  row.add("mb_in_core_max", m.mb_in_core_max);  // INFOG(16)
  row.add("mb_in_core_sum", m.mb_in_core_sum);  // INFOG(17)
  row.add("mb_ooc_max", m.mb_ooc_max);          // INFOG(26)
  row.add("mb_ooc_sum", m.mb_ooc_sum);          // INFOG(27)
  auto join = [](const std::vector<double>& v) {
    std::string s;
    for (double x : v) s += (s.empty() ? "" : " ") + num(x);
    return s;
  };
  row.add("factor_entries_rank", join(m.factor_entries_rank));  // INFO(3)
  row.add("mb_in_core_rank", join(m.mb_in_core_rank));
  row.add("mb_ooc_rank", join(m.mb_ooc_rank));
  row.add("flops", m.flops);
  row.add("factor_entries_used", m.factor_entries);  // INFOG(9), after a factorization
  row.add("mb_used_max", m.mb_used_max);
  row.add("mb_used_sum", m.mb_used_sum);
}

// This process's CPU time so far (every thread, user and system): with the wall time, it tells a phase that
// waited for the cores (a loaded machine) from one whose threads spun or worked more.
double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// DistributedMumps on every rank: analysis, factorization, solve; the times are rank 0's (the phases are
// collective, so every rank leaves them together).
DenseMat run_distributed(const Options& o, ThesisSystem& t, Index n, Row& row) {
  SolverOptions so;
  so.ordering = o.ordering;
  so.block_size = o.system == "tf" ? 3 : 1;
  so.factor_dir = o.factor_dir;
  so.pivot_singularity_test = false;  // as the deformers: the structure decides singularity (docs/numerics.md)
  DistributedMumps dm(so);
  std::vector<int> rows, cols;
  std::vector<double> vals;
  my_entries(t.K, o.input == "root", rows, cols, o.analysis_only ? nullptr : &vals);
  if (o.analysis_only || mpi::rank() != 0) SpMat().swap(t.K);  // only rank 0's residual reads K again
  Timer ta;
  dm.analyze(n, std::move(rows), std::move(cols));
  row.add("analyze_s", ta.seconds());
  DenseMat x;
  if (!o.analysis_only) {
    Timer tf;
    const double c0 = cpu_seconds();
    dm.factorize(std::move(vals));
    row.add("factorize_s", tf.seconds());
    row.add("factorize_cpu_s", cpu_seconds() - c0);  // rank 0's
    x = mpi::rank() == 0 ? t.rhs : DenseMat();
    Timer ts;
    const double c1 = cpu_seconds();
    dm.solve(x);
    row.add("solve_s", ts.seconds());
    row.add("solve_cpu_s", cpu_seconds() - c1);
  }
  add_report(row, dm.report());
  row.add("ordering_used", dm.stats().ordering_used);
  return x;
}

// DistributedMumps's analysis of the pattern that rank 0 passes whole (centralized input); the others pass none.
void run_centralized(const Options& o, ThesisPattern& t, Index n, Row& row) {
  SolverOptions so;
  so.ordering = o.ordering;
  so.block_size = o.system == "tf" ? 3 : 1;
  DistributedMumps dm(so);
  std::vector<int> rows, cols;
  if (mpi::rank() == 0) pattern_entries(t, rows, cols);
  std::vector<int>().swap(t.pattern.colptr);
  std::vector<int>().swap(t.pattern.rows);
  Timer ta;
  const double c0 = cpu_seconds();
  dm.analyze_centralized(n, std::move(rows), std::move(cols));
  row.add("analyze_s", ta.seconds());
  row.add("analyze_cpu_s", cpu_seconds() - c0);  // rank 0's
  add_report(row, dm.report());
  row.add("ordering_used", dm.stats().ordering_used);
}

// One registry backend in this process (the comparison's other side).
DenseMat run_single(const Options& o, const ThesisSystem& t, Row& row) {
  SolverOptions so;
  so.ordering = o.ordering;
  so.block_size = t.block;
  so.factor_dir = o.factor_dir;
  so.pivot_singularity_test = false;
  auto solver = make_solver(o.solver, so);
  Timer ta;
  solver->analyze(t.K);
  row.add("analyze_s", ta.seconds());
  DenseMat x;
  if (!o.analysis_only) {
    Timer tf;
    const double c0 = cpu_seconds();
    solver->factorize(t.K);
    row.add("factorize_s", tf.seconds());
    row.add("factorize_cpu_s", cpu_seconds() - c0);
    Timer ts;
    const double c1 = cpu_seconds();
    solver->solve(t.rhs, x);
    row.add("solve_s", ts.seconds());
    row.add("solve_cpu_s", cpu_seconds() - c1);
  }
  const FactorStats st = solver->stats();
  row.add("flops", st.flops);
  row.add("factor_entries", double(st.nnz_factor));
  row.add("ordering_used", st.ordering_used);
  return x;
}

// Residual, --positions, --compare (rank 0).
void finish_solution(const Options& o, const ThesisSystem& t, const DenseMat& x, Row& row) {
  const DenseMat r = t.K.selfadjointView<Eigen::Upper>() * x - t.rhs;
  row.add("residual", r.norm() / t.rhs.norm());
  const Points P = Eigen::Map<const Points>(x.data(), x.size() / 3, 3);
  if (!o.positions.empty()) write_positions(o.positions, P);
  if (!o.compare.empty()) {
    const Points Q = read_positions(o.compare);
    if (Q.rows() != P.rows()) throw InputError(fmt::format("--compare {}: {} rows, this solution has {}", o.compare,
                                                           Q.rows(), P.rows()));
    row.add("max_diff_vs_compare", (P - Q).cwiseAbs().maxCoeff());
  }
}

int run(const Options& o) {
  const bool distributed = o.solver == "distributed", centralized = o.input == "centralized";
  if (!distributed && mpi::launched() && mpi::size() > 1)
    throw UsageError("--solver " + o.solver + " runs in one process: start it without mpirun, or use distributed");
  if (centralized && !(distributed && o.analysis_only))
    throw UsageError("--input centralized is an analysis of the pattern: --solver distributed --analysis-only");
  if (!o.csv.empty()) cli::check_output("--csv", o.csv, {".csv"}, {o.mesh});
  const bool builds = !distributed || o.input == "split" || mpi::rank() == 0;
  ThesisSystem t = builds && !centralized ? build_thesis_system(o.mesh, o.system) : ThesisSystem{};
  ThesisPattern tp = builds && centralized ? build_thesis_pattern(o.mesh, o.system) : ThesisPattern{};
  std::vector<double> sizes{centralized ? double(tp.n()) : double(t.K.cols()),
                            centralized ? double(tp.nnz_upper()) : double(t.K.nonZeros()),
                            double(centralized ? tp.vertices : t.vertices), centralized ? tp.build_s : t.build_s};
  if (distributed) mpi::broadcast(sizes);
  const Index n = Index(sizes[0]);
  const double built_ranks = distributed ? mpi::sum_all(builds ? 1.0 : 0.0) : 1.0;
  Row row;
  row.add("model", o.label.empty() ? std::string(std::filesystem::path(o.mesh).stem()) : o.label);
  row.add("system", o.system);
  row.add("vertices", sizes[2]);
  row.add("n", double(n));
  row.add("nnz_upper", sizes[1]);
  row.add("solver", distributed ? "mumps_distributed" : o.solver);
  row.add("ranks", distributed ? mpi::size() : 1);
  row.add("input", distributed ? o.input : "whole");
  row.add("ordering", o.ordering);
  row.add("factor_storage", o.factor_dir.empty() ? "memory" : "disk");
  row.add("phases", o.analysis_only ? "analysis" : "all");
  row.add("build_s", sizes[3]);
  row.add("built_ranks", built_ranks);
  DenseMat x;
  if (centralized) run_centralized(o, tp, n, row);
  else x = distributed ? run_distributed(o, t, n, row) : run_single(o, t, row);
  const std::vector<double> rss = distributed ? mpi::gather_to_root(double(peak_rss_bytes()))
                                              : std::vector<double>{double(peak_rss_bytes())};
  if (distributed && mpi::rank() != 0) return 0;
  row.add("peak_rss_max_bytes", *std::max_element(rss.begin(), rss.end()));
  std::string per_rank;
  for (double b : rss) per_rank += (per_rank.empty() ? "" : " ") + num(b);
  row.add("peak_rss_rank_bytes", per_rank);
  if (!o.analysis_only) finish_solution(o, t, x, row);
  std::string line;
  for (const auto& [k, v] : row.cols) line += (line.empty() ? "" : " ") + k + "=" + v;
  std::cout << line << "\n[mumps_ranks] " << provenance_summary() << "\n";
  if (!o.csv.empty()) {
    CsvTable csv;
    csv.add(row.cols);
    csv.write(o.csv);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("One system by MUMPS on every rank of an MPI launch, or by one backend in one process.",
               "exp_mumps_ranks");
  Options o;
  define_options(app, o);
  const int code = db::cli::run(app, argc, argv, [&] { return run(o); });
  if (code != 0 && db::mpi::launched() && db::mpi::size() > 1) db::mpi::abort_all(code);  // leave none waiting
  return code;
}
