#pragma once
//! METIS's random draws, kept per thread, so that METIS orderings can run on several threads at once.
//!
//! Debian's METIS 5.1 draws its random numbers from the C library's rand(), reseeded by srand() at the start of
//! every call. glibc keeps one generator for the whole process: two orderings on two threads would interleave
//! their draws and come out different from run to run. metis_random.cpp therefore defines rand() and srand()
//! (they interpose glibc's for the whole process: the dynamic linker finds an executable's symbols first, and
//! METIS imports both): glibc's own generator (random_r with the state srand seeds), one per thread. Each thread
//! then draws the sequence a single-threaded process draws, so an ordering computed on any thread is the one the
//! serial run computes, bit for bit.

namespace db {

//! Whether METIS's draws are per thread in this process: the rand() the dynamic linker resolves (the one METIS
//! calls) is metis_random.cpp's. False where the executable does not export it (then orderings run serially,
//! with the same result). Checked once.
bool metis_draws_per_thread();

}  // namespace db
