#pragma once
//! Dense kernels of the multifrontal solves on one panel of a FactorBlock (storage.h): T its packed w x w
//! diagonal triangle, Rr its h x w rectangle below, x a column-major block of r right-hand sides (leading
//! dimension ldx) from the panel's first row: w entries of the panel's own columns, then the h rows below.
//!
//! Why hand-written and not the BLAS: the solves stream through the factor once per direction, bound by memory
//! bandwidth and by dependent adds, and the BLAS handles a few right-hand sides poorly (dgemm with n = 1..3).
//! These are plain loops that read each column of L from memory once and from cache for the further right-hand
//! sides; the backward ones are register-blocked (several columns of L, or whole rows of x, at a time). Compiled
//! for the baseline ISA and for x86-64-v3 (AVX2, FMA), chosen when the library loads. Each takes the factor's
//! entries in double or in float (the mixed backend's rounded factor: half the bytes to stream), and computes in
//! double: a float entry is widened exactly, so the float kernels do what the double ones do on the rounded
//! entries.

namespace db::multifrontal {

//! Forward substitution on a panel: x_j /= L_jj, then x_i -= L_ij x_j below j; the rows under the panel start
//! at zero and end as -L_rs y_s.
void forward_panel(const double* T, const double* Rr, int w, int h, int r, double* x, int ldx);
void forward_panel(const float* T, const float* Rr, int w, int h, int r, double* x, int ldx);

//! Backward substitution on a panel: x_j = (x_j - sum_{i>j} L_ij x_i) / L_jj for r right-hand sides, column by
//! column of x.
void backward_panel(const double* T, const double* Rr, int w, int h, int r, double* x, int ldx);
void backward_panel(const float* T, const float* Rr, int w, int h, int r, double* x, int ldx);

//! backward_panel for two to four right-hand sides held row by row: row k of x in lanes 0..3 of x + 4k (unused
//! lanes zero).
void backward_rows4(const double* T, const double* Rr, int w, int h, double* x);
void backward_rows4(const float* T, const float* Rr, int w, int h, double* x);

//! The rectangles' parts of the panel kernels, on a range of it (a tile of the top supernodes' solves, which a
//! team of threads shares): forward_panel's for rows i0 .. i1 - 1 of the h below the panel, after its triangle
//! (forward_panel with h = 0); backward_panel's and backward_rows4's for the panel's columns j0 .. j1 - 1, before
//! its triangle (those kernels with h = 0). Each row's or column's result is the one the whole kernel gives it.
void forward_rect(const double* Rr, int w, int h, int i0, int i1, int r, double* x, int ldx);
void forward_rect(const float* Rr, int w, int h, int i0, int i1, int r, double* x, int ldx);
void backward_rect(const double* Rr, int w, int h, int j0, int j1, int r, double* x, int ldx);
void backward_rect(const float* Rr, int w, int h, int j0, int j1, int r, double* x, int ldx);
void backward_rows4_rect(const double* Rr, int w, int h, int j0, int j1, double* x);
void backward_rows4_rect(const float* Rr, int w, int h, int j0, int j1, double* x);

}  // namespace db::multifrontal
