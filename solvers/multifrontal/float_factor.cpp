#include "solvers/multifrontal/float_factor.h"

#include <algorithm>
#include <new>
#include <vector>

#include <fmt/format.h>

#include "core/error.h"
#include "solvers/multifrontal/storage.h"

namespace db::multifrontal {
namespace {

//! Panel p of a FactorBlock of m rows, n columns: where its packed triangle starts (entries from the block's
//! start), its width and the height of its rectangle. Panels are stored one after the other.
struct PanelAt {
  std::size_t tri;
  int c0, w, h;
};
std::vector<PanelAt> panels_of(int m, int n) {
  std::vector<PanelAt> out;
  std::size_t at = 0;
  for (int c0 = 0; c0 < n; c0 += FactorBlock::kWidth) {
    const int w = std::min(FactorBlock::kWidth, n - c0), h = m - c0 - w;
    out.push_back({at, c0, w, h});
    at += std::size_t(w) * std::size_t(w + 1) / 2 + std::size_t(w) * std::size_t(h);
  }
  return out;
}

}  // namespace

FloatFactor::FloatFactor(const FactorView& F) : entries_(F.S.xptr.back()) {
  values_.reset(new (std::nothrow) float[std::max<std::size_t>(entries_, 1)]);
  if (!values_)
    throw BudgetError(fmt::format("multifrontal_mixed: cannot allocate {} MB for the single-precision factor",
                                  bytes() >> 20));
  std::vector<double> buf;
  for (int s = 0; s < F.S.nsuper(); ++s) {
    const std::size_t a = F.S.xptr[std::size_t(s)], count = F.S.xptr[std::size_t(s) + 1] - a;
    const double* src = F.values.get() + a;
    if (F.values.on_file()) {  // read back, not faulted into the mapping (Mapping::read)
      buf.resize(count);
      F.values.read(src, count, buf.data());
      src = buf.data();
    }
    std::transform(src, src + count, values_.get() + a, [](double v) { return static_cast<float>(v); });
  }
}

void FloatFactor::solve(const Symbolic& S, RowMajorMat& y) const {
  std::vector<double> x;
  for (int s = 0; s < S.nsuper(); ++s) forward(S, s, y, x);  // supernodes are in postorder
  for (int s = S.nsuper() - 1; s >= 0; --s) backward(S, s, y, x);
}

//! x (row-major, r a row) := L_s^{-1} x on the supernode's rows, then the rows below are added to y.
void FloatFactor::forward(const Symbolic& S, int s, RowMajorMat& y, std::vector<double>& x) const {
  const int m = S.nrows(s), nc = S.ncols(s), f = S.col0[std::size_t(s)];
  const std::size_t r = std::size_t(y.cols());
  const int* R = S.rows.data() + S.rptr[std::size_t(s)];
  x.assign(std::size_t(m) * r, 0.0);
  for (int k = 0; k < nc; ++k) std::copy_n(y.row(f + k).data(), r, x.data() + std::size_t(k) * r);
  const float* base = values_.get() + S.xptr[std::size_t(s)];
  for (const PanelAt& P : panels_of(m, nc)) {
    const float* tri = base + P.tri;
    const float* rect = tri + std::size_t(P.w) * std::size_t(P.w + 1) / 2;
    double* xc = x.data() + std::size_t(P.c0) * r;
    for (int j = 0; j < P.w; ++j) {
      const float* col = tri + packed_column(j, P.w);
      double* xj = xc + std::size_t(j) * r;
      for (std::size_t c = 0; c < r; ++c) xj[c] /= double(col[0]);
      for (int i = j + 1; i < P.w; ++i)
        for (std::size_t c = 0; c < r; ++c) xc[std::size_t(i) * r + c] -= double(col[i - j]) * xj[c];
    }
    double* below = xc + std::size_t(P.w) * r;
    for (int j = 0; j < P.w; ++j) {
      const float* rc = rect + std::size_t(j) * std::size_t(P.h);
      const double* xj = xc + std::size_t(j) * r;
      for (int i = 0; i < P.h; ++i)
        for (std::size_t c = 0; c < r; ++c) below[std::size_t(i) * r + c] -= double(rc[i]) * xj[c];
    }
  }
  for (int k = 0; k < nc; ++k) std::copy_n(x.data() + std::size_t(k) * r, r, y.row(f + k).data());
  for (int k = nc; k < m; ++k)
    for (std::size_t c = 0; c < r; ++c) y(R[k], Index(c)) += x[std::size_t(k) * r + c];
}

//! x_s := L_s^{-T} (x_s - L_rs^T x_rows), panels last to first.
void FloatFactor::backward(const Symbolic& S, int s, RowMajorMat& y, std::vector<double>& x) const {
  const int m = S.nrows(s), nc = S.ncols(s), f = S.col0[std::size_t(s)];
  const std::size_t r = std::size_t(y.cols());
  const int* R = S.rows.data() + S.rptr[std::size_t(s)];
  x.resize(std::size_t(m) * r);
  for (int k = 0; k < m; ++k) std::copy_n(y.row(k < nc ? f + k : R[k]).data(), r, x.data() + std::size_t(k) * r);
  const float* base = values_.get() + S.xptr[std::size_t(s)];
  const std::vector<PanelAt> panels = panels_of(m, nc);
  for (auto P = panels.rbegin(); P != panels.rend(); ++P) {
    const float* tri = base + P->tri;
    const float* rect = tri + std::size_t(P->w) * std::size_t(P->w + 1) / 2;
    double* xc = x.data() + std::size_t(P->c0) * r;
    const double* below = xc + std::size_t(P->w) * r;
    for (int j = 0; j < P->w; ++j) {
      const float* rc = rect + std::size_t(j) * std::size_t(P->h);
      double* xj = xc + std::size_t(j) * r;
      for (int i = 0; i < P->h; ++i)
        for (std::size_t c = 0; c < r; ++c) xj[c] -= double(rc[i]) * below[std::size_t(i) * r + c];
    }
    for (int j = P->w - 1; j >= 0; --j) {
      const float* col = tri + packed_column(j, P->w);
      double* xj = xc + std::size_t(j) * r;
      for (int i = j + 1; i < P->w; ++i)
        for (std::size_t c = 0; c < r; ++c) xj[c] -= double(col[i - j]) * xc[std::size_t(i) * r + c];
      for (std::size_t c = 0; c < r; ++c) xj[c] /= double(col[0]);
    }
  }
  for (int k = 0; k < nc; ++k) std::copy_n(x.data() + std::size_t(k) * r, r, y.row(f + k).data());
}

}  // namespace db::multifrontal
