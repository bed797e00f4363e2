#pragma once
//! MPI for the MUMPS backends, without MPI types in the interface (callers above solvers/ need no mpi.h).
//!
//! Initialization on first use: a process that never called MPI_Init gets MPI_Init_thread(MULTIPLE) the first time a
//! MUMPS backend (or anything here) needs MPI, and MPI_Finalize at exit. MULTIPLE because Debian's PT-Scotch, MUMPS's
//! parallel ordering, calls MPI from several threads at once (threads_multiple). Started without mpirun it is an MPI
//! singleton (one rank); then OMPI_MCA_ess_singleton_isolated=1 is set unless the environment sets it, so Open MPI does
//! not start its runtime daemon (a forked process and a noticeable start-up for every test binary). Running as root
//! needs nothing for a singleton; mpirun itself refuses root without --allow-run-as-root (or OMPI_ALLOW_RUN_AS_ROOT=1
//! OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1), which scripts/mpirun.sh adds.
#include <cstddef>
#include <vector>

namespace db::mpi {

//! Initializes MPI if nobody has (see above). Idempotent; safe to call from any thread, one at a time.
void ensure_initialized();
//! Whether a launcher (mpirun, srun) started this process: its environment names a world of ranks. Does not
//! initialize MPI.
bool launched();
//! Whether MPI runs at MPI_THREAD_MULTIPLE, which PT-Scotch's threads need (initializes MPI). False only where the
//! caller initialized MPI at a lower level, or the MPI library offers none higher.
bool threads_multiple();
//! Rank and size of MPI_COMM_WORLD (initializes MPI).
int rank();
int size();

//! Every rank's value, in rank order, on rank 0 (empty elsewhere). Collective.
std::vector<double> gather_to_root(double value);
//! Element-wise sum of every rank's `data` into rank 0's (others keep theirs). Collective; same count everywhere.
void sum_to_root(double* data, std::size_t count);
//! Every rank's double-double numbers hi[k] + lo[k] summed in double-double (Knuth's two-sum, the low parts
//! renormalized) into rank 0's hi and lo (others keep theirs): a sum of the ranks' shares of an extended-precision
//! residual whose rounding happens once, on rank 0. Collective; same count everywhere.
void sum_double_double_to_root(double* hi, double* lo, std::size_t count);
//! Rank 0's `data` on every rank (resized to rank 0's size). Collective.
void broadcast(std::vector<int>& data);
void broadcast(std::vector<double>& data);
//! The largest / smallest / sum of every rank's value, on every rank. Collective.
double max_all(double value);
double min_all(double value);
double sum_all(double value);
//! Whether every rank passed the same `count` ints (their count and a 64-bit hash compared). Collective.
bool same_on_every_rank(const int* data, std::size_t count);
//! Ends every rank of the world with `code` (MPI_Abort): for a failure on some ranks only, which would leave the
//! others waiting in a collective call forever.
[[noreturn]] void abort_all(int code);

}  // namespace db::mpi
