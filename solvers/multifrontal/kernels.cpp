#include "solvers/multifrontal/kernels.h"

#include <algorithm>
#include <cstddef>

#include "solvers/multifrontal/storage.h"

namespace db::multifrontal {
namespace {

//! Four doubles as one vector (an AVX2 register, or two SSE2 ones in the baseline clone); loads need not be
//! aligned, and may alias the doubles they read.
typedef double Vec4d __attribute__((vector_size(32), aligned(8), may_alias));
typedef float Vec4f __attribute__((vector_size(16), aligned(4), may_alias));

//! v := four entries of the factor from p, as doubles (a float factor's are widened exactly). Not returned by
//! value: a vector return is an ABI question outside the AVX2 clone, though these are always inlined.
inline __attribute__((always_inline)) void load4(const double* p, Vec4d& v) { v = *reinterpret_cast<const Vec4d*>(p); }
inline __attribute__((always_inline)) void load4(const float* p, Vec4d& v) {
  v = __builtin_convertvector(*reinterpret_cast<const Vec4f*>(p), Vec4d);
}

//! x_j -= sum_{i < h} Rr(i, j) x_{w + i} for the NB columns j0 .. j0 + NB - 1 of a panel's rectangle and R
//! right-hand sides (columns of x, leading dimension ldx): each entry of x is loaded once for the NB columns
//! and each entry of L once for the R right-hand sides, four partial sums per product (the compiler may not
//! reorder a floating-point sum itself), NB x R of them in flight to hide the adds' latency. One dot product per
//! column and right-hand side loaded both operands for every multiply-add, and was slower on TF's frames.
template <int NB, int R, class E>
inline __attribute__((always_inline)) void rect_dots(const E* Rr, std::size_t sh, int j0, int w, int h,
                                                     double* x, int ldx) {
  Vec4d acc[NB][R];
  for (int k = 0; k < NB; ++k)
    for (int c = 0; c < R; ++c) acc[k][c] = Vec4d{0, 0, 0, 0};
  const E* q[NB];
  for (int k = 0; k < NB; ++k) q[k] = Rr + std::size_t(j0 + k) * sh;
  const double* xs[R];
  for (int c = 0; c < R; ++c) xs[c] = x + std::size_t(c) * std::size_t(ldx) + std::size_t(w);
  int i = 0;
  for (; i + 4 <= h; i += 4) {
    Vec4d xv[R];
    for (int c = 0; c < R; ++c) xv[c] = *reinterpret_cast<const Vec4d*>(xs[c] + i);
    for (int k = 0; k < NB; ++k) {
      Vec4d qv;
      load4(q[k] + i, qv);
      for (int c = 0; c < R; ++c) acc[k][c] += qv * xv[c];
    }
  }
  for (int k = 0; k < NB; ++k)
    for (int c = 0; c < R; ++c) {
      double sum = (acc[k][c][0] + acc[k][c][2]) + (acc[k][c][1] + acc[k][c][3]);
      for (int t = i; t < h; ++t) sum += q[k][t] * xs[c][t];
      x[std::size_t(c) * std::size_t(ldx) + std::size_t(j0 + k)] -= sum;
    }
}

//! The rectangle's part of backward_panel for R right-hand sides and the panel's columns j0 .. j1 - 1: NB
//! columns at a time (NB x R accumulators and NB + R loads per step fit the sixteen vector registers), then the
//! remaining columns one by one. Each column's sum is its own, whatever columns share its step.
template <int NB, int R, class E>
inline __attribute__((always_inline)) void rect_solve(const E* Rr, int w, int h, int j0, int j1, double* x, int ldx) {
  const std::size_t sh = std::size_t(h);
  int j = j0;
  for (; j + NB <= j1; j += NB) rect_dots<NB, R>(Rr, sh, j, w, h, x, ldx);
  for (; j < j1; ++j) rect_dots<1, R>(Rr, sh, j, w, h, x, ldx);
}

//! x_j -= sum_{i < h} Rr(i, j) x_{w + i} for the NB columns from j0, x held row by row as in backward_rows4.
template <int NB, class E>
inline __attribute__((always_inline)) void rows4_rect(const E* Rr, std::size_t sh, int j0, int w, int h,
                                                      double* x) {
  Vec4d acc[NB];
  for (int k = 0; k < NB; ++k) acc[k] = Vec4d{0, 0, 0, 0};
  const E* q = Rr + std::size_t(j0) * sh;
  const double* xb = x + 4 * std::size_t(w);
  for (int i = 0; i < h; ++i) {
    const Vec4d xi = *reinterpret_cast<const Vec4d*>(xb + 4 * std::size_t(i));
    for (int k = 0; k < NB; ++k) {
      const double l = q[std::size_t(k) * sh + std::size_t(i)];
      acc[k] += Vec4d{l, l, l, l} * xi;
    }
  }
  for (int k = 0; k < NB; ++k) *reinterpret_cast<Vec4d*>(x + 4 * std::size_t(j0 + k)) -= acc[k];
}

//! The rectangle's part of forward_panel for its rows i0 .. i1 - 1, four columns at a time (one pass over those
//! rows of x per four columns of L, each column read from memory once for all right-hand sides). Each row's sum
//! is its own, whatever rows share the call.
template <class E>
inline __attribute__((always_inline)) void forward_rect_of(const E* Rr, int w, int h, int i0, int i1, int r,
                                                           double* x, int ldx) {
  const std::size_t sh = std::size_t(h);
  int j = 0;
  for (; j + 3 < w; j += 4) {
    const E *q0 = Rr + std::size_t(j) * sh, *q1 = q0 + sh, *q2 = q1 + sh, *q3 = q2 + sh;
    for (int c = 0; c < r; ++c) {
      double* xc = x + std::size_t(c) * std::size_t(ldx);
      const double v0 = xc[j], v1 = xc[j + 1], v2 = xc[j + 2], v3 = xc[j + 3];
      double* xr = xc + w;
      for (int i = i0; i < i1; ++i) xr[i] -= (q0[i] * v0 + q1[i] * v1) + (q2[i] * v2 + q3[i] * v3);
    }
  }
  for (; j < w; ++j) {
    const E* q = Rr + std::size_t(j) * sh;
    for (int c = 0; c < r; ++c) {
      double* xc = x + std::size_t(c) * std::size_t(ldx);
      const double v = xc[j];
      double* xr = xc + w;
      for (int i = i0; i < i1; ++i) xr[i] -= q[i] * v;
    }
  }
}

//! The triangle first, then the rectangle.
template <class E>
inline __attribute__((always_inline)) void forward_panel_of(const E* T, const E* Rr, int w, int h, int r, double* x,
                                                            int ldx) {
  for (int j = 0; j < w; ++j) {
    const E* t = T + packed_column(j, w);  // t[i - j] = L_ij, i = j .. w - 1
    for (int c = 0; c < r; ++c) {
      double* xc = x + std::size_t(c) * std::size_t(ldx);
      const double v = (xc[j] /= t[0]);
      for (int i = 1; i < w - j; ++i) xc[j + i] -= t[i] * v;
    }
  }
  forward_rect_of(Rr, w, h, 0, h, r, x, ldx);
}

//! The rectangle's dot products for the panel's columns j0 .. j1 - 1 (independent of each other: the rows below
//! are final).
template <class E>
inline __attribute__((always_inline)) void backward_rect_of(const E* Rr, int w, int h, int j0, int j1, int r,
                                                            double* x, int ldx) {
  if (h > 0)
    for (int c = 0; c < r;) {  // one (TF's); more than four (backward_rows4 takes two to four) three at a time
      double* xc = x + std::size_t(c) * std::size_t(ldx);
      switch (std::min(r - c, 3)) {
        case 3: rect_solve<2, 3>(Rr, w, h, j0, j1, xc, ldx); c += 3; break;
        case 2: rect_solve<2, 2>(Rr, w, h, j0, j1, xc, ldx); c += 2; break;
        default: rect_solve<4, 1>(Rr, w, h, j0, j1, xc, ldx); c += 1; break;
      }
    }
}

//! The rectangle's dot products first, then the triangle bottom up.
template <class E>
inline __attribute__((always_inline)) void backward_panel_of(const E* T, const E* Rr, int w, int h, int r, double* x,
                                                             int ldx) {
  backward_rect_of(Rr, w, h, 0, w, r, x, ldx);
  for (int j = w - 1; j >= 0; --j) {
    const E* t = T + packed_column(j, w);
    for (int c = 0; c < r; ++c) {
      double* xc = x + std::size_t(c) * std::size_t(ldx);
      double sum = 0;
      for (int i = 1; i < w - j; ++i) sum += t[i] * xc[j + i];
      xc[j] = (xc[j] - sum) / t[0];
    }
  }
}

//! Each entry of L is one multiply-add on a whole row of x, with no horizontal sums. With LAP's three
//! right-hand sides on small supernodes (most of a mesh system's) the general kernel's per-column dot products
//! were mostly reductions and tails, and its frames took several times one pass over the factor at the memory
//! read rate.
template <class E>
inline __attribute__((always_inline)) void backward_rows4_rect_of(const E* Rr, int w, int h, int j0, int j1,
                                                                  double* x) {
  const std::size_t sh = std::size_t(h);
  int j = j0;
  for (; j + 8 <= j1; j += 8) rows4_rect<8>(Rr, sh, j, w, h, x);
  for (; j + 4 <= j1; j += 4) rows4_rect<4>(Rr, sh, j, w, h, x);
  for (; j < j1; ++j) rows4_rect<1>(Rr, sh, j, w, h, x);
}

template <class E>
inline __attribute__((always_inline)) void backward_rows4_of(const E* T, const E* Rr, int w, int h, double* x) {
  if (h > 0) backward_rows4_rect_of(Rr, w, h, 0, w, x);
  auto row = [x](int i) -> Vec4d& { return *reinterpret_cast<Vec4d*>(x + 4 * std::size_t(i)); };
  for (int j = w - 1; j >= 0; --j) {  // the triangle bottom up, two partial sums (the adds' latency)
    const E* t = T + packed_column(j, w);
    Vec4d s0{0, 0, 0, 0}, s1{0, 0, 0, 0};
    int i = 1;
    for (; i + 1 < w - j; i += 2) {
      s0 += Vec4d{t[i], t[i], t[i], t[i]} * row(j + i);
      s1 += Vec4d{t[i + 1], t[i + 1], t[i + 1], t[i + 1]} * row(j + i + 1);
    }
    if (i < w - j) s0 += Vec4d{t[i], t[i], t[i], t[i]} * row(j + i);
    row(j) = (row(j) - (s0 + s1)) / Vec4d{t[0], t[0], t[0], t[0]};
  }
}

}  // namespace

// The kernels for each type of factor entries, each compiled for both ISAs (target_clones does not take
// templates): the computation is in double either way.
#define DB_KERNEL __attribute__((target_clones("arch=x86-64-v3", "default")))
DB_KERNEL void forward_panel(const double* T, const double* Rr, int w, int h, int r, double* x, int ldx) {
  forward_panel_of(T, Rr, w, h, r, x, ldx);
}
DB_KERNEL void forward_panel(const float* T, const float* Rr, int w, int h, int r, double* x, int ldx) {
  forward_panel_of(T, Rr, w, h, r, x, ldx);
}
DB_KERNEL void backward_panel(const double* T, const double* Rr, int w, int h, int r, double* x, int ldx) {
  backward_panel_of(T, Rr, w, h, r, x, ldx);
}
DB_KERNEL void backward_panel(const float* T, const float* Rr, int w, int h, int r, double* x, int ldx) {
  backward_panel_of(T, Rr, w, h, r, x, ldx);
}
DB_KERNEL void backward_rows4(const double* T, const double* Rr, int w, int h, double* x) {
  backward_rows4_of(T, Rr, w, h, x);
}
DB_KERNEL void backward_rows4(const float* T, const float* Rr, int w, int h, double* x) {
  backward_rows4_of(T, Rr, w, h, x);
}
DB_KERNEL void forward_rect(const double* Rr, int w, int h, int i0, int i1, int r, double* x, int ldx) {
  forward_rect_of(Rr, w, h, i0, i1, r, x, ldx);
}
DB_KERNEL void forward_rect(const float* Rr, int w, int h, int i0, int i1, int r, double* x, int ldx) {
  forward_rect_of(Rr, w, h, i0, i1, r, x, ldx);
}
DB_KERNEL void backward_rect(const double* Rr, int w, int h, int j0, int j1, int r, double* x, int ldx) {
  backward_rect_of(Rr, w, h, j0, j1, r, x, ldx);
}
DB_KERNEL void backward_rect(const float* Rr, int w, int h, int j0, int j1, int r, double* x, int ldx) {
  backward_rect_of(Rr, w, h, j0, j1, r, x, ldx);
}
DB_KERNEL void backward_rows4_rect(const double* Rr, int w, int h, int j0, int j1, double* x) {
  backward_rows4_rect_of(Rr, w, h, j0, j1, x);
}
DB_KERNEL void backward_rows4_rect(const float* Rr, int w, int h, int j0, int j1, double* x) {
  backward_rows4_rect_of(Rr, w, h, j0, j1, x);
}
#undef DB_KERNEL

}  // namespace db::multifrontal
