#include "solvers/mumps_distributed.h"

#include <cmath>

#include <mpi.h>

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "solvers/mumps_instance.h"
#include "solvers/mumps_mpi.h"
#include "solvers/solver_util.h"

namespace db {
namespace {

constexpr const char* kWho = "mumps (distributed)";

//! Every rank's flag, and-ed: a rank whose own input is bad makes all of them throw, so none is left waiting in
//! the next collective call.
bool all_ranks(bool ok) { return mpi::min_all(ok ? 1.0 : 0.0) > 0; }

}  // namespace

DistributedMumps::DistributedMumps(const SolverOptions& options) : options_(options) {
  solver_util::check_options(options, "mumps");
  if (options.ordering == "metis")
    throw Error(fmt::format("{}: ordering metis needs the whole graph on one rank; order the unknowns beforehand and "
                            "pass natural, or let MUMPS order (default, amd, ..., ptscotch)", kWho));
  mpi::ensure_initialized();
}

DistributedMumps::~DistributedMumps() = default;

void DistributedMumps::take_entries(Index n, std::vector<int> rows, std::vector<int> cols) {
  std::string bad;
  if (rows.size() != cols.size()) bad = fmt::format("{} rows against {} columns", rows.size(), cols.size());
  for (std::size_t k = 0; k < rows.size() && bad.empty(); ++k)
    if (rows[k] < 0 || cols[k] >= n || rows[k] > cols[k])
      bad = fmt::format("entry ({}, {}) is out of range or below the diagonal of {} x {}", rows[k], cols[k], n, n);
  if (!all_ranks(bad.empty()))
    throw Error(fmt::format("{}: rank {}: {}", kWho, mpi::rank(), bad.empty() ? "another rank's input is bad" : bad));
  irn_ = std::move(rows);
  jcn_ = std::move(cols);
  for (int& i : irn_) ++i;  // MUMPS counts from 1
  for (int& j : jcn_) ++j;
}

void DistributedMumps::analyze(Index n, std::vector<int> rows, std::vector<int> cols) {
  take_entries(n, std::move(rows), std::move(cols));
  centralized_ = false;
  mumps_ = std::make_unique<mumps::Instance>(MPI_COMM_WORLD, options_, kWho, true);
  DMUMPS_STRUC_C& id = mumps_->id();
  id.n = MUMPS_INT(n);
  id.nnz_loc = MUMPS_INT8(irn_.size());
  id.irn_loc = irn_.data();
  id.jcn_loc = jcn_.data();
  run_analysis(n);
}

void DistributedMumps::analyze_centralized(Index n, std::vector<int> rows, std::vector<int> cols) {
  if (!all_ranks(mpi::rank() == 0 || rows.empty()))
    throw Error(fmt::format("{}: centralized input: only rank 0 passes entries", kWho));
  take_entries(n, std::move(rows), std::move(cols));
  centralized_ = true;
  mumps_ = std::make_unique<mumps::Instance>(MPI_COMM_WORLD, options_, kWho, false);
  DMUMPS_STRUC_C& id = mumps_->id();
  id.n = MUMPS_INT(n);
  if (mpi::rank() == 0) {
    id.nnz = MUMPS_INT8(irn_.size());
    id.irn = irn_.data();
    id.jcn = jcn_.data();
  }
  run_analysis(n);
}

void DistributedMumps::run_analysis(Index n) {
  std::vector<int> identity;
  if (options_.ordering == "natural" && mpi::rank() == 0) {
    identity.resize(std::size_t(n));
    for (Index i = 0; i < n; ++i) identity[std::size_t(i)] = int(i) + 1;
  }
  mumps_->analyze(&identity);
  stats_ = FactorStats{};
  stats_.n = std::size_t(n);
  stats_.nnz_matrix = std::size_t(mpi::sum_all(double(irn_.size())));
  stats_.ordering_used = mumps_->ordering_used();
}

void DistributedMumps::factorize(std::vector<double> values) {
  if (!mumps_) throw SolverError(fmt::format("{}: factorize() before analyze()", kWho));
  if (centralized_) throw SolverError(fmt::format("{}: analyze_centralized() is an analysis only", kWho));
  std::string bad;
  if (values.size() != irn_.size())
    bad = fmt::format("{} values for {} analyzed entries", values.size(), irn_.size());
  for (std::size_t k = 0; k < values.size() && bad.empty(); ++k)
    if (!std::isfinite(values[k]))
      bad = fmt::format("non-finite matrix entry {} at ({}, {})", values[k], irn_[k] - 1, jcn_[k] - 1);
  if (!all_ranks(bad.empty()))
    throw SolverError(fmt::format("{}: rank {}: {}", kWho, mpi::rank(), bad.empty() ? "another rank's input is bad" : bad));
  values_ = std::move(values);
  // Scaled here, not by MUMPS (mumps_instance.h): every rank needs the scale of any row it holds.
  scaling_ = mumps::diagonal_scaling(diagonal_on_root());
  mpi::broadcast(scaling_);
  for (std::size_t k = 0; k < values_.size(); ++k)
    values_[k] *= scaling_[std::size_t(irn_[k] - 1)] * scaling_[std::size_t(jcn_[k] - 1)];
  mumps_->id().a_loc = values_.data();
  mumps_->factorize(options_.pivot_singularity_test);
  mumps_->fill_stats(stats_);
}

void DistributedMumps::solve(DenseMat& BX) {
  if (!mumps_ || !mumps_->factored()) throw SolverError(fmt::format("{}: solve() before a successful factorize()", kWho));
  // Rank 0's right-hand sides: their count, and whether they fit, on every rank (all throw, or none).
  std::vector<int> shape{int(BX.cols()), BX.rows() == Index(stats_.n) ? 1 : 0};
  mpi::broadcast(shape);
  if (shape[1] == 0)
    throw SolverError(fmt::format("{}: right-hand side has {} rows on rank 0, system has {}", kWho, BX.rows(), stats_.n));
  DMUMPS_STRUC_C& id = mumps_->id();
  id.nrhs = shape[0];
  id.lrhs = MUMPS_INT(stats_.n);
  const Eigen::Map<const DenseVec> s(scaling_.data(), Index(scaling_.size()));
  if (mpi::rank() == 0) BX = s.asDiagonal() * BX;  // S A S (S^-1 x) = S b
  id.rhs = mpi::rank() == 0 ? BX.data() : nullptr;
  mumps_->solve();
  id.rhs = nullptr;
  if (mpi::rank() == 0) BX = s.asDiagonal() * BX;
  if (!all_ranks(mpi::rank() != 0 || BX.allFinite())) {
    if (mpi::rank() == 0) solver_util::check_finite_result(BX, kWho);  // names the entry
    throw SolverError(fmt::format("{}: the solution on rank 0 is not finite", kWho));
  }
}

std::vector<double> DistributedMumps::diagonal_on_root() const {
  // Each rank's diagonal entries (index, value) gathered to rank 0 and summed there: no rank holds n values but it.
  std::vector<double> mine;
  for (std::size_t k = 0; k < irn_.size(); ++k)
    if (irn_[k] == jcn_[k]) mine.insert(mine.end(), {double(irn_[k] - 1), values_[k]});
  const int count = int(mine.size()), ranks = mpi::size(), me = mpi::rank();
  std::vector<int> counts(std::size_t(me == 0 ? ranks : 0)), offsets(counts.size() + 1, 0);
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  for (std::size_t r = 0; r < counts.size(); ++r) offsets[r + 1] = offsets[r] + counts[r];
  std::vector<double> all(std::size_t(offsets.back()));
  MPI_Gatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), offsets.data(), MPI_DOUBLE, 0, MPI_COMM_WORLD);
  std::vector<double> diagonal(me == 0 ? stats_.n : 0, 0.0);
  for (std::size_t k = 0; k + 1 < all.size(); k += 2) diagonal[std::size_t(all[k])] += all[k + 1];
  return diagonal;
}

const mumps::Report& DistributedMumps::report() const {
  if (!mumps_) throw Error(fmt::format("{}: no analysis yet", kWho));
  return mumps_->report();
}

}  // namespace db
