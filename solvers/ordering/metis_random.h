#pragma once
//! METIS on several threads at once: its random draws kept per thread, its signal traps kept off the process's
//! signal handlers.
//!
//! Draws. Debian's METIS 5.1 draws its random numbers from the C library's rand(), reseeded by srand() at the start
//! of every call. glibc keeps one generator for the whole process: two orderings on two threads would interleave
//! their draws and come out different from run to run. metis_random.cpp therefore defines rand() and srand()
//! (they interpose glibc's for the whole process: the dynamic linker finds an executable's symbols first, and
//! METIS imports both): glibc's own generator (random_r with the state srand seeds), one per thread. Each thread
//! then draws the sequence a single-threaded process draws, so an ordering computed on any thread is the one the
//! serial run computes, bit for bit.
//!
//! Signals. Every METIS call sets SIGTERM and SIGABRT to its own handler with signal() and puts back what it found
//! at the end (GKlib's gk_sigtrap / gk_siguntrap, for its error exits). The dispositions are the process's: two
//! calls on two threads can put each other's handler back, leaving METIS's installed after both end, and a later
//! SIGTERM then jumps into a finished call (a crash where solvers/base/cleanup.h should clean up and exit 143); even
//! one call leaves SIGTERM to METIS while it runs. metis_random.cpp therefore also defines signal() as glibc
//! exports it to ISO C code (__sysv_signal, which METIS imports): called from libmetis it changes nothing and
//! returns the handler in place; from anywhere else it is glibc's. The cost: an error exit inside METIS (its own
//! out-of-memory) now ends the process by the signal METIS raises instead of returning an error code.

namespace db {

//! Whether METIS can run on several threads in this process: the rand(), srand() and __sysv_signal() the dynamic
//! linker resolves (the ones METIS calls) are metis_random.cpp's. False where the executable does not export them
//! (then orderings run serially, with the same result). Checked once.
bool metis_on_threads();

}  // namespace db
