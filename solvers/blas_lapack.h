#pragma once
//! The one include for BLAS and LAPACK in the project; nothing else declares their routines.
//!  - LAPACK: the reference LAPACK's own prototypes of its Fortran routines (<lapack.h>, installed with
//!    liblapacke-dev). Call them through the LAPACK_xxx macros (LAPACK_dpotrf(uplo, n, a, lda, info)): these pass
//!    gfortran's hidden CHARACTER lengths, which keeps the calls well-defined. The routines themselves come from
//!    the system LAPACK (OpenBLAS on Debian), not from liblapacke, which the project does not link.
//!  - BLAS: the C interface (<cblas.h>), declared by the system BLAS itself; OpenBLAS implements it on the same
//!    kernels as the Fortran entry points.
//! Why not LAPACKE's C functions: they add a library that only wraps these routines, and its high-level calls scan
//! every input for NaN and allocate work arrays; the multifrontal backend calls dpotrf on thousands of small
//! diagonal blocks and the backends check their input for non-finite values once, themselves.
#include <complex>

// C++ types for lapack.h's complex arguments (its default, C99 _Complex, is not C++).
#ifndef lapack_complex_float
#define lapack_complex_float std::complex<float>
#endif
#ifndef lapack_complex_double
#define lapack_complex_double std::complex<double>
#endif

#include <cblas.h>
#include <lapack.h>
