//! Name -> factory table of every backend.
#include <functional>
#include <limits>

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "solvers/backends.h"
#include "solvers/linear_solver.h"
#include "solvers/ordering/suitesparse_memory.h"

namespace db {
namespace {

using Factory = std::function<std::unique_ptr<LinearSolver>(const SolverOptions&)>;

struct Entry {
  SolverInfo info;
  Factory make;
};

const std::vector<Entry>& table() {
  static const std::vector<std::string> kCholmodOrderings = {"default", "amd", "metis", "nesdis", "natural"};
  static const std::vector<std::string> kDenseOrderings = {"default", "natural"};
  static const std::vector<Entry> entries = {
      {{"cholmod_supernodal", "sparse-cholesky", true, kCholmodOrderings},
       [](const SolverOptions& o) { return backends::make_cholmod(true, o); }},
      {{"multifrontal", "sparse-cholesky", true, kCholmodOrderings, true, true, true},
       [](const SolverOptions& o) { return backends::make_multifrontal(o); }},
      // Single-precision factor, CG refinement in double to SolverOptions::tolerance (it throws when it does not
      // get there).
      {{"multifrontal_mixed", "sparse-cholesky", true, kCholmodOrderings, true, true, true},
       [](const SolverOptions& o) { return backends::make_multifrontal(o, backends::Precision::Mixed); }},
      // The double factor with the same refinement: the exact solution of the system, to the tolerance.
      {{"multifrontal_refined", "sparse-cholesky", true, kCholmodOrderings, true, true, true},
       [](const SolverOptions& o) { return backends::make_multifrontal(o, backends::Precision::Refined); }},
#ifdef DEFORMBENCH_HAVE_MUMPS  // absent from a build configured without MUMPS (CMakeLists.txt)
      {{"mumps", "sparse-cholesky", true, backends::mumps_orderings(), true, false},
       [](const SolverOptions& o) { return backends::make_mumps(o); }},
      // MUMPS's double factor with multifrontal_refined's refinement, on one process or under mpirun: the exact
      // solution of a distributed run. Distributed input on one process too, so no "metis" (it needs the whole
      // graph on one rank).
      {{"mumps_refined", "sparse-cholesky", true, backends::mumps_refined_orderings(), true, false},
       [](const SolverOptions& o) { return backends::make_mumps_on_ranks(o, true); }},
#endif
      {{"cholmod_simplicial_ldlt", "sparse-cholesky", true, kCholmodOrderings},
       [](const SolverOptions& o) { return backends::make_cholmod(false, o); }},
      {{"dense_llt", "dense", true, kDenseOrderings},
       [](const SolverOptions& o) { return backends::make_dense("llt", o); }},
      {{"lapack_potrf", "dense", true, kDenseOrderings},
       [](const SolverOptions& o) { return backends::make_dense("potrf", o); }},
      // Bunch-Kaufman factors indefinite matrices too; it only refuses singular ones.
      {{"dense_ldlt_bk", "dense", false, kDenseOrderings},
       [](const SolverOptions& o) { return backends::make_dense("ldlt_bk", o); }},
      {{"dense_lu", "dense", false, kDenseOrderings},
       [](const SolverOptions& o) { return backends::make_dense("lu", o); }},
      {{"eigen_simplicial_llt", "sparse-cholesky", true, {"default", "amd", "natural"}},
       [](const SolverOptions& o) { return backends::make_eigen_simplicial(false, o); }},
      {{"eigen_simplicial_ldlt", "sparse-cholesky", true, {"default", "amd", "natural"}},
       [](const SolverOptions& o) { return backends::make_eigen_simplicial(true, o); }},
      {{"eigen_sparse_lu", "sparse-lu", false, {"default", "colamd", "amd", "natural"}},
       [](const SolverOptions& o) { return backends::make_eigen_sparse_lu(o); }},
      {{"umfpack", "sparse-lu", false, {"default", "amd", "metis", "natural"}},
       [](const SolverOptions& o) { return backends::make_umfpack(o); }},
      // CG may converge on an indefinite system; it throws when it does not.
      {{"cg_jacobi", "iterative", false, {"default", "natural"}},
       [](const SolverOptions& o) { return backends::make_cg(false, o); }},
      {{"cg_ichol", "iterative", false, {"default", "amd"}},
       [](const SolverOptions& o) { return backends::make_cg(true, o); }},
  };
  return entries;
}

const Entry& find(const std::string& name) {
  for (const Entry& e : table())
    if (e.info.name == name) return e;
  throw Error(fmt::format("unknown solver '{}' (valid: {})", name, fmt::join(solver_names(), ", ")));
}

}  // namespace

std::unique_ptr<LinearSolver> make_solver(const std::string& name, const SolverOptions& options) {
  const Entry& e = find(name);
  use_huge_pages_in_suitesparse();
  if (!options.factor_dir.empty() && !e.info.out_of_core) {
    std::vector<std::string> can;
    for (const Entry& o : table())
      if (o.info.out_of_core) can.push_back(o.info.name);
    throw Error(fmt::format("{}: cannot keep its factor out of core (factor directory '{}'); {} can", name,
                            options.factor_dir, fmt::join(can, " and ")));
  }
  if (options.rank_shares != 1 && name != "mumps" && name != "mumps_refined")
    throw Error(fmt::format("{}: takes the whole system in one process; only mumps and mumps_refined sum the shares "
                            "of {} ranks",
                            name, options.rank_shares));
  return e.make(options);
}

std::vector<std::string> solver_names() {
  std::vector<std::string> names;
  for (const Entry& e : table()) names.push_back(e.info.name);
  return names;
}

SolverInfo solver_info(const std::string& name) { return find(name).info; }

void LinearSolver::factorize_dense(DenseMat& full) {
  full = DenseMat();
  std::vector<std::string> dense;
  for (const Entry& e : table())
    if (e.info.family == "dense") dense.push_back(e.info.name);
  throw Error(fmt::format("{}: takes sparse input only; a dense matrix needs a dense backend ({})", name(),
                          fmt::join(dense, ", ")));
}

double singular_pivot_bound(std::size_t n) { return 10.0 * double(n) * std::numeric_limits<double>::epsilon(); }

}  // namespace db
