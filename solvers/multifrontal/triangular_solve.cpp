#include "solvers/multifrontal/triangular_solve.h"

#include <algorithm>

#include "solvers/multifrontal/kernels.h"

namespace db::multifrontal {
namespace {

//! Supernode s's place in the solves: its first column f, its nc columns and m rows (R: their indices, its own
//! columns first), the r right-hand sides of y (sm, sr: m and r as sizes) and y's values (row-major).
struct Place {
  int f, nc, m, r;
  const int* R;
  std::size_t sm, sr;
  double* y;
};
template <class View>
Place place(const View& F, int s, RowMajorMat& y) {
  const int m = F.S.nrows(s), r = int(y.cols());
  return {F.S.col0[std::size_t(s)], F.S.ncols(s), m, r, F.S.rows.data() + F.S.rptr[std::size_t(s)],
          std::size_t(m), std::size_t(r), y.data()};
}

//! Panel p of L as the kernels read it (its packed triangle, then its rectangle): in place in memory; out of core
//! copied into `buf` (Mapping::read), so a frame does not fault the whole factor back into the mapping.
template <class E>
struct Panel {
  const E* tri;
  const E* rect;
};
Panel<double> panel(const FactorView& F, const FactorBlock& L, int p, std::vector<double>& buf) {
  if (!F.values.on_file()) return {L.tri(p), L.rect(p)};
  const std::size_t w = std::size_t(L.width(p)), tri = w * (w + 1) / 2, count = tri + w * std::size_t(L.height(p));
  buf.resize(std::max(buf.size(), count));
  F.values.read(L.tri(p), count, buf.data());
  return {buf.data(), buf.data() + tri};
}
Panel<float> panel(const FloatFactorView&, const FactorBlockOf<const float>& L, int p, std::vector<double>&) {
  return {L.tri(p), L.rect(p)};
}

//! The top supernodes' tiles in the solves: rows of a panel's rectangle (forward), columns of a panel (backward).
//! Each tile reads a few hundred KB of a front of a few thousand rows: a team's step of several tiles per thread.
constexpr int kSolveTileRows = 256;
constexpr int kSolveTileColumns = 32;

//! A panel's forward substitution: whole, or its triangle here and its rectangle's rows on the team's threads.
template <class E>
void forward_panel_on(Team* team, const E* tri, const E* rect, int w, int h, int r, double* x, int ldx) {
  if (!team || h <= kSolveTileRows) return forward_panel(tri, rect, w, h, r, x, ldx);
  forward_panel(tri, rect, w, 0, r, x, ldx);
  const Tiles rows(h, kSolveTileRows, team);
  team->run(rows.count(), [&](int k) { forward_rect(rect, w, h, rows.first(k), rows.end(k), r, x, ldx); });
}

//! A panel's backward substitution: whole, or its rectangle's columns on the team's threads and its triangle here.
template <class E>
void backward_panel_on(Team* team, const E* tri, const E* rect, int w, int h, int r, double* x, int ldx) {
  if (!team || h == 0 || w <= kSolveTileColumns) return backward_panel(tri, rect, w, h, r, x, ldx);
  const Tiles columns(w, kSolveTileColumns, team);
  team->run(columns.count(), [&](int k) { backward_rect(rect, w, h, columns.first(k), columns.end(k), r, x, ldx); });
  backward_panel(tri, rect, w, 0, r, x, ldx);
}

//! backward_panel_on for backward_rows4's layout.
template <class E>
void backward_rows4_on(Team* team, const E* tri, const E* rect, int w, int h, double* x) {
  if (!team || h == 0 || w <= kSolveTileColumns) return backward_rows4(tri, rect, w, h, x);
  const Tiles columns(w, kSolveTileColumns, team);
  team->run(columns.count(), [&](int k) { backward_rows4_rect(rect, w, h, columns.first(k), columns.end(k), x); });
  backward_rows4(tri, rect, w, 0, x);
}

}  // namespace

double solve_flops(const Symbolic& S, Index r) { return 2.0 * double(S.nnz) * double(r); }

template <class View>
void forward_supernode(const View& F, int s, RowMajorMat& y_, SolveScratch& scratch, const ForeignRows* foreign,
                       Team* team) {
  const auto [f, nc, m, r, R, sm, sr, y] = place(F, s, y_);
  std::vector<double>& tmp = scratch.rhs;
  tmp.assign(sm * sr, 0.0);
  for (int k = 0; k < nc; ++k)
    for (int c = 0; c < r; ++c) tmp[std::size_t(c) * sm + std::size_t(k)] = y[std::size_t(f + k) * sr + std::size_t(c)];
  const auto L = F.block(s);
  for (int p = 0; p < L.panels(); ++p) {
    const auto P = panel(F, L, p, scratch.panel);
    forward_panel_on(team, P.tri, P.rect, L.width(p), L.height(p), r, tmp.data() + L.c0(p), m);
  }
  for (int k = 0; k < nc; ++k)
    for (int c = 0; c < r; ++c) y[std::size_t(f + k) * sr + std::size_t(c)] = tmp[std::size_t(c) * sm + std::size_t(k)];
  double* acc = foreign ? foreign->acc.data() : nullptr;
  for (int k = nc; k < m; ++k) {
    const int i = R[k];
    double* dst = (!foreign || foreign->owner[std::size_t(i)] == foreign->thread ? y : acc) + std::size_t(i) * sr;
    for (int c = 0; c < r; ++c) dst[c] += tmp[std::size_t(c) * sm + std::size_t(k)];
  }
}

namespace {

//! backward_supernode for two to four right-hand sides: rows of x as vectors (backward_rows4).
template <class View>
void backward_rows(const View& F, int s, RowMajorMat& y_, SolveScratch& scratch, Team* team) {
  const auto [f, nc, m, r, R, sm, sr, y] = place(F, s, y_);
  const auto L = F.block(s);
  std::vector<double>& tmp = scratch.rhs;
  tmp.resize(sm * 4);
  double* x = tmp.data();
  for (int k = 0; k < m; ++k) {  // plain loops: a few doubles a row, not worth a library call
    const double* src = y + std::size_t(k < nc ? f + k : R[k]) * sr;
    for (int c = 0; c < 4; ++c) x[4 * std::size_t(k) + std::size_t(c)] = c < r ? src[c] : 0.0;
  }
  for (int p = L.panels() - 1; p >= 0; --p) {
    const auto P = panel(F, L, p, scratch.panel);
    backward_rows4_on(team, P.tri, P.rect, L.width(p), L.height(p), x + 4 * std::size_t(L.c0(p)));
  }
  for (int k = 0; k < nc; ++k)
    for (int c = 0; c < r; ++c) y[std::size_t(f + k) * sr + std::size_t(c)] = x[4 * std::size_t(k) + std::size_t(c)];
}

}  // namespace

template <class View>
void backward_supernode(const View& F, int s, RowMajorMat& y_, SolveScratch& scratch, Team* team) {
  if (y_.cols() >= 2 && y_.cols() <= 4) return backward_rows(F, s, y_, scratch, team);  // the general kernel otherwise
  const auto [f, nc, m, r, R, sm, sr, y] = place(F, s, y_);
  const auto L = F.block(s);
  std::vector<double>& tmp = scratch.rhs;
  tmp.resize(sm * sr);
  for (int k = 0; k < m; ++k) {
    const double* src = y + std::size_t(k < nc ? f + k : R[k]) * sr;
    for (int c = 0; c < r; ++c) tmp[std::size_t(c) * sm + std::size_t(k)] = src[c];
  }
  for (int p = L.panels() - 1; p >= 0; --p) {
    const auto P = panel(F, L, p, scratch.panel);
    backward_panel_on(team, P.tri, P.rect, L.width(p), L.height(p), r, tmp.data() + L.c0(p), m);
  }
  for (int k = 0; k < nc; ++k)
    for (int c = 0; c < r; ++c) y[std::size_t(f + k) * sr + std::size_t(c)] = tmp[std::size_t(c) * sm + std::size_t(k)];
}

template <class View>
void forward_all(const View& F, const Plan& plan, RowMajorMat& y, std::vector<RowMajorMat>& acc) {
  const Index n = F.S.n, r = y.cols();
  const std::size_t T = plan.subtrees.size();
  acc.resize(T);
  for (auto& a : acc) {
    a.resize(n, r);
    for (int j : plan.top_columns) a.row(j).setZero();
  }
  run_subtrees(T, worth_threads(solve_flops(F.S, r), Work::Solve), [&](std::size_t t) {
    SolveScratch tmp;
    const ForeignRows foreign{int(t), plan.owner, acc[t]};
    for (int root : plan.subtrees[t])
      for (int s = F.S.first[std::size_t(root)]; s <= root; ++s) forward_supernode(F, s, y, tmp, &foreign);
  });
  for (std::size_t t = 0; t < T; ++t)
    for (int j : plan.top_columns) y.row(j) += acc[t].row(j);
  SolveScratch tmp;
  Team team(plan.top.empty() ? 1 : plan.top_team);
  for (int s : plan.top) forward_supernode(F, s, y, tmp, nullptr, team.size() > 1 ? &team : nullptr);
}

template <class View>
void backward_all(const View& F, const Plan& plan, RowMajorMat& y) {
  SolveScratch tmp;
  {
    Team team(plan.top.empty() ? 1 : plan.top_team);
    for (auto it = plan.top.rbegin(); it != plan.top.rend(); ++it)
      backward_supernode(F, *it, y, tmp, team.size() > 1 ? &team : nullptr);
  }
  run_subtrees(plan.subtrees.size(), worth_threads(solve_flops(F.S, y.cols()), Work::Solve), [&](std::size_t t) {
    SolveScratch tmp_t;
    for (auto it = plan.subtrees[t].rbegin(); it != plan.subtrees[t].rend(); ++it)
      for (int s = *it; s >= F.S.first[std::size_t(*it)]; --s) backward_supernode(F, s, y, tmp_t);
  });
}

template void forward_supernode(const FactorView&, int, RowMajorMat&, SolveScratch&, const ForeignRows*, Team*);
template void forward_supernode(const FloatFactorView&, int, RowMajorMat&, SolveScratch&, const ForeignRows*, Team*);
template void backward_supernode(const FactorView&, int, RowMajorMat&, SolveScratch&, Team*);
template void backward_supernode(const FloatFactorView&, int, RowMajorMat&, SolveScratch&, Team*);
template void forward_all(const FactorView&, const Plan&, RowMajorMat&, std::vector<RowMajorMat>&);
template void forward_all(const FloatFactorView&, const Plan&, RowMajorMat&, std::vector<RowMajorMat>&);
template void backward_all(const FactorView&, const Plan&, RowMajorMat&);
template void backward_all(const FloatFactorView&, const Plan&, RowMajorMat&);

}  // namespace db::multifrontal
