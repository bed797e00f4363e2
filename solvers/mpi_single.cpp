//! solvers/mumps_mpi.h for a build without MUMPS and MPI (CMakeLists.txt: DEFORMBENCH_HAVE_MUMPS off): one
//! process is the whole world. A process a launcher started as one of several ranks is refused by name (rank()
//! throws), since every rank would otherwise run the whole job on its own and write the same outputs.
#include <cstdlib>

#include "solvers/base/error.h"
#include "solvers/mumps_mpi.h"

namespace db::mpi {
namespace {
int world_size_from_launcher() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "SLURM_STEP_NUM_TASKS"})
    if (const char* s = std::getenv(v)) return std::atoi(s);
  return 1;
}
}  // namespace

void ensure_initialized() {
  if (world_size_from_launcher() > 1)
    throw Error("started on several ranks, but this build has no MPI (MUMPS was not found when it was configured)");
}
bool launched() { return world_size_from_launcher() > 1; }
int rank() {
  ensure_initialized();
  return 0;
}
//! The launcher's world, so that callers see they were started on several ranks; rank() then refuses.
int size() { return world_size_from_launcher(); }
std::vector<double> gather_to_root(double value) { return {value}; }
void sum_to_root(double*, std::size_t) {}
void sum_double_double_to_root(double*, double*, std::size_t) {}
void broadcast(std::vector<int>&) {}
void broadcast(std::vector<double>&) {}
double max_all(double value) { return value; }
double min_all(double value) { return value; }
double sum_all(double value) { return value; }
bool same_on_every_rank(const int*, std::size_t) { return true; }
[[noreturn]] void abort_all(int code) { std::exit(code); }

}  // namespace db::mpi
