#include "solvers/mumps_mpi.h"

#include <climits>
#include <cstdint>
#include <cstdlib>
#include <mutex>

#include <fmt/format.h>
#include <mpi.h>

#include "solvers/base/error.h"

namespace db::mpi {
namespace {

std::mutex init_mutex;

void finalize_at_exit() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized) MPI_Finalize();
}

void check(int status, const char* what) {
  if (status == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int len = 0;
  MPI_Error_string(status, text, &len);
  throw SolverError(fmt::format("MPI: {} failed: {}", what, std::string(text, std::size_t(len))));
}

int count_of(std::size_t n, const char* what) {
  if (n > std::size_t(INT_MAX)) throw SolverError(fmt::format("MPI: {} of {} elements exceeds one message", what, n));
  return int(n);
}

}  // namespace

bool launched() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "SLURM_STEP_NUM_TASKS"})
    if (std::getenv(v)) return true;
  return false;
}

void ensure_initialized() {
  const std::lock_guard<std::mutex> lock(init_mutex);
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (initialized) return;
  if (!launched()) setenv("OMPI_MCA_ess_singleton_isolated", "1", 0);  // 0: an explicit setting wins
  // MULTIPLE, not the SERIALIZED this file's own calls need: Debian's PT-Scotch (MUMPS's "ptscotch" ordering) runs
  // MPI collectives from several of its threads at once, and under SERIALIZED Open MPI crashed in them now and then.
  int provided = 0;
  check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_MULTIPLE, &provided), "MPI_Init_thread");
  std::atexit(finalize_at_exit);
}

bool threads_multiple() {
  ensure_initialized();
  int provided = 0;
  MPI_Query_thread(&provided);
  return provided >= MPI_THREAD_MULTIPLE;
}

int rank() {
  ensure_initialized();
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

int size() {
  ensure_initialized();
  int s = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &s);
  return s;
}

std::vector<double> gather_to_root(double value) {
  std::vector<double> all(rank() == 0 ? std::size_t(size()) : 0);
  check(MPI_Gather(&value, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, 0, MPI_COMM_WORLD), "MPI_Gather");
  return all;
}

void sum_to_root(double* data, std::size_t count) {
  const int n = count_of(count, "a sum");
  if (rank() == 0)
    check(MPI_Reduce(MPI_IN_PLACE, data, n, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD), "MPI_Reduce");
  else
    check(MPI_Reduce(data, nullptr, n, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD), "MPI_Reduce");
}

namespace {

//! MPI_Op on pairs (hi, lo): inout := in + inout in double-double. The file is compiled with -ffp-contract=off
//! (solvers/CMakeLists.txt): a fused step would break the error-free sum.
void add_double_double(void* in, void* inout, int* len, MPI_Datatype*) {
  const double* a = static_cast<const double*>(in);
  double* b = static_cast<double*>(inout);
  for (int k = 0; k < 2 * *len; k += 2) {
    const double s = a[k] + b[k], v = s - a[k];
    const double e = (a[k] - (s - v)) + (b[k] - v);  // a + b = s + e exactly
    const double lo = e + a[k + 1] + b[k + 1];
    b[k] = s + lo;  // renormalized: |lo| below half an ulp of hi
    b[k + 1] = lo - (b[k] - s);
  }
}

}  // namespace

void sum_double_double_to_root(double* hi, double* lo, std::size_t count) {
  const int n = count_of(count, "a double-double sum");
  std::vector<double> pairs(2 * count);
  for (std::size_t k = 0; k < count; ++k) {
    pairs[2 * k] = hi[k];
    pairs[2 * k + 1] = lo[k];
  }
  MPI_Datatype pair;
  MPI_Op op;
  check(MPI_Type_contiguous(2, MPI_DOUBLE, &pair), "MPI_Type_contiguous");
  check(MPI_Type_commit(&pair), "MPI_Type_commit");
  check(MPI_Op_create(&add_double_double, 1, &op), "MPI_Op_create");
  const int rc = rank() == 0 ? MPI_Reduce(MPI_IN_PLACE, pairs.data(), n, pair, op, 0, MPI_COMM_WORLD)
                             : MPI_Reduce(pairs.data(), nullptr, n, pair, op, 0, MPI_COMM_WORLD);
  MPI_Op_free(&op);
  MPI_Type_free(&pair);
  check(rc, "MPI_Reduce");
  if (rank() != 0) return;
  for (std::size_t k = 0; k < count; ++k) {
    hi[k] = pairs[2 * k];
    lo[k] = pairs[2 * k + 1];
  }
}

namespace {
template <class T>
void broadcast_vector(std::vector<T>& data, MPI_Datatype type) {
  unsigned long long n = data.size();
  check(MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD), "MPI_Bcast");
  data.resize(std::size_t(n));
  check(MPI_Bcast(data.data(), count_of(data.size(), "a broadcast"), type, 0, MPI_COMM_WORLD), "MPI_Bcast");
}
double reduce_all(double value, MPI_Op op) {
  ensure_initialized();
  double out = value;
  check(MPI_Allreduce(&value, &out, 1, MPI_DOUBLE, op, MPI_COMM_WORLD), "MPI_Allreduce");
  return out;
}
}  // namespace

void broadcast(std::vector<int>& data) {
  ensure_initialized();
  broadcast_vector(data, MPI_INT);
}
void broadcast(std::vector<double>& data) {
  ensure_initialized();
  broadcast_vector(data, MPI_DOUBLE);
}
double max_all(double value) { return reduce_all(value, MPI_MAX); }
double min_all(double value) { return reduce_all(value, MPI_MIN); }
double sum_all(double value) { return reduce_all(value, MPI_SUM); }

bool same_on_every_rank(const int* data, std::size_t count) {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a
  for (std::size_t k = 0; k < count; ++k) h = (h ^ std::uint32_t(data[k])) * 1099511628211ull;
  bool same = true;
  for (const double v : {double(count), double(h >> 32), double(h & 0xffffffffu)})  // each exact in a double
    same = (max_all(v) == min_all(v)) && same;
  return same;
}

void abort_all(int code) {
  ensure_initialized();
  MPI_Abort(MPI_COMM_WORLD, code);
  std::_Exit(code);  // MPI_Abort does not return; this is for the compiler
}

}  // namespace db::mpi
