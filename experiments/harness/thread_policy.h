#pragma once
//! How a solver cell at T threads sets the three threading layers a backend can use, so that two pools never
//! both run T threads on T cores (OpenBLAS here is the pthread build, which does not know of OpenMP: a BLAS call
//! from inside an OpenMP region starts its own T threads, and the pools' idle threads spin while the other works):
//!
//!   backend                         OMP_NUM_THREADS  OPENBLAS_NUM_THREADS  DEFORMBENCH_THREADS
//!   cholmod_*, umfpack, spqr        1                T                     T
//!   multifrontal*                   1                T                     T   (its subtree tasks set the BLAS to 1)
//!   mumps*                          T                1                     T
//!   every other (dense, eigen, cg)  1                T                     T
//!
//! SuiteSparse's OpenMP loops (CHOLMOD's supernodal assembly) are scatter loops beside BLAS-3 calls that do the
//! flops, so the BLAS gets the threads (CHOLMOD's loops name their thread count in the build, which
//! OMP_NUM_THREADS does not lower: the backend runs them on one thread itself, solver_util.h OpenMpSerial); MUMPS runs its own OpenMP over fronts and calls the BLAS inside them, so
//! OpenMP gets them; the project's multifrontal backend runs its subtree tasks on DEFORMBENCH_THREADS and sets the
//! BLAS to one thread inside them itself. DEFORMBENCH_THREADS also sets the cell's structured assembly.
#include <string>

namespace db::harness {

struct ThreadSettings {
  int omp = 1, blas = 1, own = 1;
  std::string text() const;  //!< "omp=1 blas=4 own=4"
};

//! The settings of `backend` at `threads` (>= 1).
ThreadSettings thread_settings(const std::string& backend, int threads);

//! Sets OMP_NUM_THREADS, OPENBLAS_NUM_THREADS and DEFORMBENCH_THREADS in this process's environment, for the
//! children it starts next (the libraries read them when they load).
void export_thread_settings(const ThreadSettings& s);

}  // namespace db::harness
