#include "solvers/multifrontal/front.h"

#include <algorithm>
#include <functional>

#include "solvers/blas_lapack.h"

namespace db::multifrontal {
namespace {

//! Front column j of supernode s's FactorBlock L: entries of rows j .. split - 1 are tri[row], those of
//! rows split .. m - 1 are rect[row - split] (rows as front positions).
struct FrontColumn {
  double *tri, *rect;
  int split;
};
FrontColumn front_column(const FactorBlock& L, int j) {
  const int p = j / FactorBlock::kWidth, c0 = L.c0(p), w = L.width(p);
  return {L.tri(p) + packed_column(j - c0, w) - std::size_t(j),
          L.rect(p) + std::size_t(j - c0) * std::size_t(L.height(p)), c0 + w};
}

//! The top phase's tiles: rows of a product, and columns of a child's update matrix in an extend-add. Large
//! enough that a tile's BLAS call runs near the one-thread dgemm rate; small enough that a front of a few thousand
//! rows gives each thread of a many-core machine several tiles.
constexpr int kTileRows = 128;
constexpr int kTileColumns = 64;

//! fn(0) .. fn(tiles - 1): on the team's threads, or in order on this one (the subtree phase, where a wrapped
//! call per small front would cost).
template <class Fn>
void run_tiles(Team* team, int tiles, const Fn& fn) {
  if (team)
    team->run(tiles, std::function<void(int)>(std::cref(fn)));
  else
    for (int t = 0; t < tiles; ++t) fn(t);
}

//! d[0 .. n) += s[0 .. n): one contiguous run of an extend-add, which the compiler vectorizes.
void add_run(double* __restrict d, const double* __restrict s, int n) {
  for (int k = 0; k < n; ++k) d[k] += s[k];
}

}  // namespace

FrontFactorization::FrontFactorization(const Symbolic& S, double* values, std::vector<double>& pivots,
                                       std::size_t pool_bytes)
    : S_(S), values_(values), pivots_(pivots), pool_(pool_bytes / sizeof(double)), updates_(std::size_t(S.nsuper())) {}

void FrontFactorization::assemble_child(int c, int p, Workspace& ws, Part part, Team* team) {
  const int nc = S_.ncols(p), m = S_.nrows(p), nr = m - nc;
  const int* R = S_.rows.data() + S_.rptr[std::size_t(p)];
  for (int k = 0; k < m; ++k) ws.map[std::size_t(R[k])] = k;
  const FactorBlock L = block(p);
  const int ncc = S_.ncols(c), nrc = S_.nrows(c) - ncc;
  const int* Rc = S_.rows.data() + S_.rptr[std::size_t(c)] + ncc;
  ws.rel.resize(std::size_t(nrc));
  for (int k = 0; k < nrc; ++k) ws.rel[std::size_t(k)] = ws.map[std::size_t(Rc[k])];
  const int* rel = ws.rel.data();
  // end[k]: the end of the run of consecutive parent rows that k's row starts or continues. Each run is added
  // as one contiguous block: the same single addition per entry as entry by entry, so the same bytes.
  ws.run_end.resize(std::size_t(nrc));
  int* end = ws.run_end.data();
  for (int k = nrc - 1; k >= 0; --k) end[k] = k + 1 < nrc && rel[k + 1] == rel[k] + 1 ? end[k + 1] : k + 1;
  // Rows ascend, so the columns landing in p's own columns come first.
  const int jsplit = int(std::lower_bound(rel, rel + nrc, nc) - rel);
  const UpdateBlock& Uc = updates_[std::size_t(c)];
  UpdateBlock* U = nullptr;
  if ((part & kUpdate) && jsplit < nrc) {
    U = &updates_[std::size_t(p)];
    if (!*U) *U = UpdateBlock(nr, true, &pool_);
  }
  // Each column of the child's matrix lands in a column of its own, so column tiles never write the same entry.
  const Tiles columns(nrc, kTileColumns, team);
  run_tiles(team, columns.count(), [&](int t) {
    const int j0 = columns.first(t), j1 = columns.end(t);
    if (part & kPivot)
      for (int jj = j0; jj < std::min(j1, jsplit); ++jj) {
        const double* src = Uc.col(jj) - jj;  // src[ii] = entry (ii, jj)
        const FrontColumn col = front_column(L, rel[jj]);
        for (int ii = jj; ii < nrc;) {
          const int r = rel[ii];
          const int e = r < col.split ? std::min(end[ii], ii + col.split - r) : end[ii];
          add_run(r < col.split ? col.tri + r : col.rect + (r - col.split), src + ii, e - ii);
          ii = e;
        }
      }
    if (U)
      for (int jj = std::max(j0, jsplit); jj < j1; ++jj) {
        const int lj = rel[jj] - nc;
        const double* src = Uc.col(jj) - jj;
        double* dst = U->col(lj) - lj - nc;  // dst[k] = entry (k - nc, lj) of U
        for (int ii = jj; ii < nrc; ii = end[ii]) add_run(dst + rel[ii], src + ii, end[ii] - ii);
      }
  });
  if ((part & kUpdate) || jsplit == nrc) updates_[std::size_t(c)] = UpdateBlock();
}

//! Its FactorBlock starts as the mapping's zero pages, and may already hold some children's updates.
//! When s's update matrix is a fresh heap block, the children's entries for it are added after s's own
//! product has written it (beta = 0), so it is never zero-filled: that fill was a visible part of the
//! extend-add time. Mapped update matrices come zeroed from the kernel anyway: they take the children whole
//! first, so that the largest children's matrices are not kept any longer.
bool FrontFactorization::factor_supernode(const MatrixChunk& M, int s, Workspace& ws, Team* team) {
  const int nr = S_.nrows(s) - S_.ncols(s);
  const FactorBlock L = block(s);
  const int* kids = S_.child.data() + S_.cptr[std::size_t(s)];
  const int nkids = S_.cptr[std::size_t(s) + 1] - S_.cptr[std::size_t(s)];
  // Not begun by children assembled early (top supernodes), and not mapped.
  const bool fresh_heap = nr > 0 && !updates_[std::size_t(s)] && !UpdateBlock::mapped(nr);
  for (int q = 0; q < nkids; ++q)
    if (updates_[std::size_t(kids[q])]) assemble_child(kids[q], s, ws, fresh_heap ? kPivot : kBoth, team);
  add_matrix_entries(M, s, L, ws);
  if (!factor_panels(s, L, ws, team)) return false;
  if (nr > 0) {
    form_update(s, L, fresh_heap, ws, team);
    if (fresh_heap)
      for (int q = 0; q < nkids; ++q)
        if (updates_[std::size_t(kids[q])]) assemble_child(kids[q], s, ws, kUpdate, team);
  }
  return true;
}

//! Matrix entries A(i, j), j in supernode s, i >= j: every such i is a row of the front.
void FrontFactorization::add_matrix_entries(const MatrixChunk& M, int s, const FactorBlock& L, Workspace& ws) const {
  const int f = S_.col0[std::size_t(s)], nc = S_.ncols(s), m = S_.nrows(s);
  const int* R = S_.rows.data() + S_.rptr[std::size_t(s)];
  for (int k = 0; k < m; ++k) ws.map[std::size_t(R[k])] = k;
  for (int j = f; j < f + nc; ++j) {
    const FrontColumn col = front_column(L, j - f);
    const int* rows = M.rows(j);
    const double* values = M.values(j);
    for (int t = 0, e = M.count(j); t < e; ++t) {
      const int k = ws.map[std::size_t(rows[t])];
      (k < col.split ? col.tri[k] : col.rect[k - col.split]) += values[t];
    }
  }
}

//! Left-looking over the panels: apply the earlier panels, factor the diagonal block, solve the rectangle.
bool FrontFactorization::factor_panels(int s, const FactorBlock& L, Workspace& ws, Team* team) {
  const int f = S_.col0[std::size_t(s)];
  const int K = FactorBlock::kWidth;
  double* D = ws.diag.data();
  for (int q = 0; q < L.panels(); ++q) {
    const int c0 = L.c0(q), w = L.width(q), h = L.height(q);
    double* T = L.tri(q);
    double* Rq = L.rect(q);
    for (int j = 0; j < w; ++j)
      std::copy(T + packed_column(j, w), T + packed_column(j + 1, w), D + std::size_t(j) * std::size_t(w + 1));
    const Tiles rows(h, kTileRows, team);
    if (q > 0)  // tile 0: the diagonal block; tile 1 + k: row tile k of the rectangle
      run_tiles(team, 1 + rows.count(), [&](int t) {
        for (int p = 0; p < q; ++p) {
          const double* Rp = L.rect(p) + (c0 - L.c0(p) - K);  // panel p's rows from c0 down
          const int ldp = L.height(p);
          if (t == 0) {
            cblas_dsyrk(CblasColMajor, CblasLower, CblasNoTrans, w, K, -1.0, Rp, ldp, 1.0, D, w);
          } else {
            const int r0 = rows.first(t - 1);
            cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, rows.size(t - 1), w, K, -1.0, Rp + w + r0, ldp, Rp,
                        ldp, 1.0, Rq + r0, h);
          }
        }
      });
    int info = 0;
    LAPACK_dpotrf("L", &w, D, &w, &info);
    if (info != 0) {
      std::int64_t expected = -1;
      failed_column_.compare_exchange_strong(expected, std::int64_t(f + c0 + std::max(info, 1) - 1));
      return false;
    }
    run_tiles(team, rows.count(), [&](int t) {
      cblas_dtrsm(CblasColMajor, CblasRight, CblasLower, CblasTrans, CblasNonUnit, rows.size(t), w, 1.0, D, w,
                  Rq + rows.first(t), h);
    });
    for (int j = 0; j < w; ++j) {
      const double l = D[std::size_t(j) * std::size_t(w + 1)];
      pivots_[std::size_t(f + c0 + j)] = l * l;
    }
    for (int j = 0; j < w; ++j)
      std::copy(D + std::size_t(j) * std::size_t(w + 1), D + std::size_t(j + 1) * std::size_t(w), T + packed_column(j, w));
  }
  return true;
}

//! Update matrix: U -= B B^T, B the rows below the supernode's columns, panel by panel of both; a fresh heap U
//! is written by the first panel's product (beta = 0). Tiles: each update panel's diagonal block, then its rows
//! below (one tile without a team), each taking every panel of B in order.
void FrontFactorization::form_update(int s, const FactorBlock& L, bool fresh_heap, Workspace& ws, Team* team) {
  const int nc = S_.ncols(s), nr = S_.nrows(s) - nc;
  UpdateBlock U = updates_[std::size_t(s)] ? std::move(updates_[std::size_t(s)]) : UpdateBlock(nr, !fresh_heap, &pool_);
  std::vector<int>& tiles = ws.tiles;  // (update panel, first row below its diagonal block or -1, rows)
  tiles.clear();
  for (int u = 0; u < U.panels(); ++u) {
    const int wu = U.width(u);
    tiles.insert(tiles.end(), {u, -1, wu});
    const Tiles below(nr - u * UpdateBlock::kWidth - wu, kTileRows, team);
    for (int k = 0; k < below.count(); ++k) tiles.insert(tiles.end(), {u, wu + below.first(k), below.size(k)});
  }
  run_tiles(team, int(tiles.size() / 3), [&](int t) {
    const int u = tiles[std::size_t(3 * t)], r0 = tiles[std::size_t(3 * t + 1)], m = tiles[std::size_t(3 * t + 2)];
    const int u0 = u * UpdateBlock::kWidth, wu = U.width(u), ldu = nr - u0;
    for (int p = 0; p < L.panels(); ++p) {
      const int wp = L.width(p), ldp = L.height(p);
      const double* B = L.rect(p) + (nc - L.c0(p) - wp);
      const double beta = fresh_heap && p == 0 ? 0.0 : 1.0;
      if (r0 < 0)
        cblas_dsyrk(CblasColMajor, CblasLower, CblasNoTrans, wu, wp, -1.0, B + u0, ldp, beta, U.panel(u), ldu);
      else
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, m, wu, wp, -1.0, B + u0 + r0, ldp, B + u0, ldp, beta,
                    U.panel(u) + r0, ldu);
    }
  });
  updates_[std::size_t(s)] = std::move(U);
}

}  // namespace db::multifrontal
