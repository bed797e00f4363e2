#include "solvers/mumps_instance.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "solvers/mumps_mpi.h"

// Indices as in the MUMPS users' guide (1-based).
#define ICNTL(I) icntl[(I) - 1]
#define INFOG(I) infog[(I) - 1]
#define INFO(I) info[(I) - 1]
#define RINFOG(I) rinfog[(I) - 1]

namespace db::mumps {
namespace {

// ICNTL(7) values (users' guide, MUMPS 5.5).
const std::map<std::string, int> kOrderingCodes = {{"default", 7}, {"amd", 0}, {"amf", 2}, {"qamd", 6}, {"pord", 4},
                                                   {"scotch", 3}, {"ptscotch", 3}, {"metis", 1}, {"natural", 1}};

//! MUMPS reports large counts in INFOG as negative millions.
double count(int v) { return v < 0 ? -1e6 * double(v) : double(v); }

void check_ooc_dir(const std::string& dir, const std::string& who) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec) || ::access(dir.c_str(), W_OK) != 0)
    throw Error(fmt::format("{}: out-of-core directory '{}' does not exist or is not writable", who, dir));
  if (dir.size() > 255)
    throw Error(fmt::format("{}: out-of-core directory '{}' is longer than MUMPS's 255 characters", who, dir));
}

}  // namespace

const SpMat& upper_triangle(const SpMat& m, SpMat& storage) {
  bool lower = false;
  for (Index j = 0; j < m.outerSize() && !lower; ++j)
    for (SpMat::InnerIterator it(m, j); it; ++it) lower = lower || it.row() > j;
  if (!lower) return m;
  storage = m.triangularView<Eigen::Upper>();
  storage.makeCompressed();
  return storage;
}

std::string error_text(int e, int i2) {
  switch (e) {
    case -1: return fmt::format("an error on process {}", i2);
    case -2: return fmt::format("the number of entries ({}) is out of range", i2);
    case -3: return "a job called out of order (e.g. factorization before analysis)";
    case -4: return fmt::format("an error in the given permutation PERM_IN (at {})", i2);
    case -5: return fmt::format("not enough memory for the analysis's real workspace ({} entries)", count(i2));
    case -6: return fmt::format("the matrix is structurally singular (structural rank {})", i2);
    case -7: return fmt::format("not enough memory for the analysis's integer workspace ({} entries)", count(i2));
    case -8: return "the integer workspace of the factorization is too small (ICNTL(14))";
    case -9: return "the real workspace of the factorization is too small (ICNTL(14))";
    case -10: return fmt::format("the matrix is numerically singular ({} pivots eliminated)", i2);
    case -11: case -12: return "the real workspace of the solve is too small";
    case -13: return fmt::format("a memory allocation failed ({} entries)", count(i2));
    case -14: case -15: return "the integer workspace of the solve is too small";
    case -16: return fmt::format("the order N ({}) is out of range", i2);
    case -17: case -20: return "an internal MPI buffer is too small";
    case -19: return "the memory limit ICNTL(23) is too small";
    case -21: case -22: case -23: return fmt::format("a misuse of the interface (code {}, {})", e, i2);
    case -40: return "the matrix is not positive definite (a negative or zero pivot in the parallel root)";
    case -51: return "the graph is too large for the 32-bit ordering library";
    case -90: return "out-of-core input/output failed (disk full or directory not writable?)";
    default: return fmt::format("MUMPS error {} ({}); see the MUMPS users' guide, error diagnostics", e, i2);
  }
}

std::string ordering_name(int code) {
  switch (code) {
    case 0: return "amd";
    case 1: return "given";
    case 2: return "amf";
    case 3: return "scotch";
    case 4: return "pord";
    case 5: return "metis";
    case 6: return "qamd";
    default: return fmt::format("mumps-{}", code);
  }
}

std::vector<std::string> orderings() {
#ifdef DB_MUMPS_SCOTCH
  return {"default", "amd", "amf", "qamd", "pord", "scotch", "ptscotch", "metis", "natural"};
#else
  return {"default", "amd", "amf", "qamd", "pord", "metis", "natural"};
#endif
}

Instance::Instance(MPI_Comm comm, const SolverOptions& options, const std::string& who, bool distributed_input)
    : comm_(comm), options_(options), who_(who), distributed_(distributed_input) {
  if (!options.factor_dir.empty()) check_ooc_dir(options.factor_dir, who);
  mpi::ensure_initialized();
  if (options.ordering == "ptscotch" && !mpi::threads_multiple())
    throw SolverError(fmt::format("{}: the ptscotch ordering needs MPI at MPI_THREAD_MULTIPLE (PT-Scotch calls MPI "
                                  "from several threads at once); this process's MPI runs at a lower level",
                                  who));
  id_.comm_fortran = MUMPS_INT(MPI_Comm_c2f(comm));
  id_.par = 1;  // the host works too
  id_.sym = 1;  // symmetric positive definite
  call(-1, "initialization");
  alive_ = true;
  const bool verbose = std::getenv("DEFORMBENCH_MUMPS_VERBOSE") != nullptr;
  id_.ICNTL(1) = verbose ? 6 : -1;
  id_.ICNTL(2) = -1;
  id_.ICNTL(3) = verbose ? 6 : -1;
  id_.ICNTL(4) = verbose ? 2 : 0;
  id_.ICNTL(8) = distributed_input ? 0 : -1;  // the diagonal scaling: see local_min_pivot
  id_.ICNTL(18) = distributed_input ? 3 : 0;
  const std::string& o = options.ordering;
  id_.ICNTL(7) = kOrderingCodes.at(o);
  given_ = o == "metis" || o == "natural";
  if (o == "ptscotch") {
    id_.ICNTL(28) = 2;
    id_.ICNTL(29) = 1;
  } else {
    id_.ICNTL(28) = 1;  // sequential analysis on the host
  }
  if (!options.factor_dir.empty()) {
    id_.ICNTL(22) = 1;
    std::snprintf(id_.ooc_tmpdir, sizeof id_.ooc_tmpdir, "%s", options.factor_dir.c_str());
    // One prefix per process: the ranks under mpirun may share the directory, and an interrupt removes exactly
    // this process's files.
    const std::string prefix = fmt::format("deformbench-mumps.{}", ::getpid());
    std::snprintf(id_.ooc_prefix, sizeof id_.ooc_prefix, "%s", prefix.c_str());
    ooc_files_ = cleanup::ScratchPath(options.factor_dir + "/" + prefix, cleanup::ScratchPath::Prefix);
  }
  MPI_Comm_size(comm, &report_.processes);
}

Instance::~Instance() {
  if (!alive_) return;
  id_.job = -2;
  dmumps_c(&id_);  // frees MUMPS's memory and its out-of-core files; nothing to report from a destructor
}

void Instance::call(int job, const char* phase) {
  id_.job = job;
  dmumps_c(&id_);
  const int e = id_.INFOG(1);
  if (e < 0) throw SolverError(fmt::format("{}: MUMPS {} failed: {}", who_, phase, error_text(e, id_.INFOG(2))));
}

void Instance::analyze(std::vector<int>* perm_in) {
  factored_ = false;
  const int b = options_.block_size;
  compressed_ = !given_ && b > 1 && id_.n % b == 0;
  id_.ICNTL(15) = compressed_ ? -b : 0;
  id_.perm_in = given_ && perm_in ? perm_in->data() : nullptr;
  call(1, "analysis");
  read_analysis_report();
}

std::vector<double> diagonal_scaling(const std::vector<double>& diagonal) {
  std::vector<double> s(diagonal.size());
  for (std::size_t k = 0; k < diagonal.size(); ++k) s[k] = diagonal[k] > 0 ? 1 / std::sqrt(diagonal[k]) : 1.0;
  return s;
}

void Instance::set_diagonal(const std::vector<double>& diagonal) {
  scaling_ = diagonal_scaling(diagonal);
  id_.colsca = scaling_.data();
  id_.rowsca = scaling_.data();
}

void Instance::factorize(bool singular_test) {
  factored_ = false;
  for (int attempt = 0;; ++attempt) {
    id_.job = 2;
    dmumps_c(&id_);
    const int e = id_.INFOG(1);
    if ((e == -8 || e == -9) && attempt < 3) {
      id_.ICNTL(14) = std::max(id_.ICNTL(14), 20) * 2;
      continue;
    }
    if (e < 0) throw SolverError(fmt::format("{}: MUMPS factorization failed: {}", who_, error_text(e, id_.INFOG(2))));
    break;
  }
  read_factor_report();
  if (id_.INFOG(33) != id_.ICNTL(8))
    throw SolverError(fmt::format("{}: MUMPS changed the scaling (ICNTL(8) {}, used {}); the pivot test would be "
                                  "meaningless", who_, id_.ICNTL(8), id_.INFOG(33)));
  const double n = double(id_.n);
  if (report_.negative_pivots > 0)
    throw SolverError(fmt::format("{}: matrix not positive definite ({} of {} pivots negative)", who_,
                                  report_.negative_pivots, id_.n));
  const double r = report_.min_pivot_ratio;
  if (!(r > 0))
    throw SolverError(fmt::format("{}: matrix not positive definite (a zero pivot of {})", who_, id_.n));
  if (singular_test && r < singular_pivot_bound(std::size_t(n)))
    throw SolverError(fmt::format("{}: matrix numerically singular (smallest pivot {:.2g} of its diagonal entry)",
                                  who_, r));
  factored_ = true;
}

void Instance::solve() {
  if (!factored_) throw SolverError(fmt::format("{}: solve() before a successful factorize()", who_));
  call(3, "solve");
}

void Instance::fill_stats(FactorStats& st) const {
  const Report& r = report_;
  st.nnz_factor = std::size_t(r.nnz_factor);
  st.flops = r.flops;
  st.factor_bytes = std::size_t(r.factor_entries * sizeof(double) + r.factor_integers * sizeof(MUMPS_INT));
  st.factor_on_disk = id_.ICNTL(22) == 1;
  const double held = st.factor_on_disk ? 0.0 : double(st.factor_bytes);
  st.workspace_bytes = std::size_t(std::max(0.0, r.mb_used_sum * 1e6 - held));
  st.min_pivot_ratio = r.min_pivot_ratio;
  st.ordering_used = ordering_used();
}

double Instance::local_min_pivot() const { return id_.dkeep[18]; }

std::string Instance::ordering_used() const {
  if (options_.ordering == "natural") return "natural";
  const std::string block = fmt::format("-block{}", options_.block_size);
  if (options_.ordering == "metis") return options_.block_size > 1 ? "metis" + block : "metis";
  // Parallel analysis (INFOG(32) = 2) reports no sequential ordering in INFOG(7).
  const std::string name = id_.INFOG(32) == 2 ? "ptscotch" : ordering_name(report_.ordering_code);
  return name + (compressed_ ? block : "");
}

void Instance::read_analysis_report() {
  const int root = 0;
  int me = 0;
  MPI_Comm_rank(comm_, &me);
  report_.ordering_code = id_.INFOG(7);
  report_.flops_estimated = id_.RINFOG(1);
  report_.nnz_factor_estimated = count(id_.INFOG(20));
  report_.mb_in_core_max = id_.INFOG(16);
  report_.mb_in_core_sum = id_.INFOG(17);
  report_.mb_ooc_max = id_.INFOG(26);
  report_.mb_ooc_sum = id_.INFOG(27);
  report_.factor_entries_estimated = count(id_.INFOG(3));
  const double mine[3] = {count(id_.INFO(3)), double(id_.INFO(15)), double(id_.INFO(17))};
  std::vector<double> all(me == root ? 3 * std::size_t(report_.processes) : 0);
  MPI_Gather(mine, 3, MPI_DOUBLE, all.data(), 3, MPI_DOUBLE, root, comm_);
  report_.factor_entries_rank.clear();
  report_.mb_in_core_rank.clear();
  report_.mb_ooc_rank.clear();
  for (std::size_t p = 0; p < all.size(); p += 3) {
    report_.factor_entries_rank.push_back(all[p]);
    report_.mb_in_core_rank.push_back(all[p + 1]);
    report_.mb_ooc_rank.push_back(all[p + 2]);
  }
}

void Instance::read_factor_report() {
  report_.flops = id_.RINFOG(3);
  report_.nnz_factor = count(id_.INFOG(29));
  report_.factor_entries = count(id_.INFOG(9));
  report_.factor_integers = count(id_.INFOG(10));
  report_.max_front = id_.INFOG(11);
  report_.mb_used_max = id_.INFOG(21);
  report_.mb_used_sum = id_.INFOG(22);
  report_.negative_pivots = id_.INFOG(12);
  double local = local_min_pivot(), global = local;
  MPI_Allreduce(&local, &global, 1, MPI_DOUBLE, MPI_MIN, comm_);
  report_.min_pivot_ratio = global;
}

}  // namespace db::mumps
