#pragma once
//! The page policy of SuiteSparse's memory (CHOLMOD, UMFPACK), made the same as this project's own.
//!
//! SuiteSparse allocates through the function pointers of SuiteSparse_config. use_huge_pages_in_suitesparse()
//! points them at malloc, calloc and realloc wrappers that ask for transparent huge pages (advise_huge_pages) on
//! every block of 4 MB or more before its first touch, as the multifrontal backend's factor storage, the
//! structured builds' matrices and the right-hand sides already do. Why: where the kernel gives huge pages only
//! on request (transparent_hugepage "madvise", Ubuntu's default and the development VM's), CHOLMOD's factor was
//! faulted in 4 KB at a time while the multifrontal backend's came 2 MB at a time, so the solver comparison
//! measured page policy as well as factorization; on a virtual machine, where each fault costs microseconds, that
//! was a fifth of CHOLMOD's factorization (results/records/2026-11-27-fresh-memory). Blocks keep being freed by
//! free(): the wrappers only add advice. Eigen's and MUMPS's allocations keep the C library's default.
namespace db {

//! Installs the wrappers, once per process (later calls do nothing). Called before the project's first
//! SuiteSparse call on each path (the solver registry, the graph analyses, the ring dissection), so that every
//! SuiteSparse block of a run gets the same policy.
void use_huge_pages_in_suitesparse();

}  // namespace db
