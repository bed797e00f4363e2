#include "solvers/multifrontal/front.h"

#include <algorithm>

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

}  // namespace

FrontFactorization::FrontFactorization(const Symbolic& S, double* values, std::vector<double>& pivots,
                                       std::size_t pool_bytes)
    : S_(S), values_(values), pivots_(pivots), pool_(pool_bytes / sizeof(double)), updates_(std::size_t(S.nsuper())) {}

void FrontFactorization::assemble_child(int c, int p, Workspace& ws, Part part) {
  const int nc = S_.ncols(p), m = S_.nrows(p), nr = m - nc;
  const int* R = S_.rows.data() + S_.rptr[std::size_t(p)];
  for (int k = 0; k < m; ++k) ws.map[std::size_t(R[k])] = k;
  const FactorBlock L = block(p);
  const int ncc = S_.ncols(c), nrc = S_.nrows(c) - ncc;
  const int* Rc = S_.rows.data() + S_.rptr[std::size_t(c)] + ncc;
  ws.rel.resize(std::size_t(nrc));
  for (int k = 0; k < nrc; ++k) ws.rel[std::size_t(k)] = ws.map[std::size_t(Rc[k])];
  const int* rel = ws.rel.data();
  // Rows ascend, so the columns landing in p's own columns come first.
  const int jsplit = int(std::lower_bound(rel, rel + nrc, nc) - rel);
  const UpdateBlock& Uc = updates_[std::size_t(c)];
  if (part & kPivot)
    for (int jj = 0; jj < jsplit; ++jj) {
      const double* src = Uc.col(jj) - jj;  // src[ii] = entry (ii, jj)
      const FrontColumn col = front_column(L, rel[jj]);
      int ii = jj;
      for (; ii < nrc && rel[ii] < col.split; ++ii) col.tri[rel[ii]] += src[ii];
      for (; ii < nrc; ++ii) col.rect[rel[ii] - col.split] += src[ii];
    }
  if ((part & kUpdate) && jsplit < nrc) {
    UpdateBlock& U = updates_[std::size_t(p)];
    if (!U) U = UpdateBlock(nr, true, &pool_);
    for (int jj = jsplit; jj < nrc; ++jj) {
      const int lj = rel[jj] - nc;
      const double* src = Uc.col(jj) - jj;
      double* dst = U.col(lj) - lj - nc;  // dst[k] = entry (k - nc, lj) of U
      for (int ii = jj; ii < nrc; ++ii) dst[rel[ii]] += src[ii];
    }
  }
  if ((part & kUpdate) || jsplit == nrc) updates_[std::size_t(c)] = UpdateBlock();
}

//! Its FactorBlock starts as the mapping's zero pages, and may already hold some children's updates.
//! When s's update matrix is a fresh heap block, the children's entries for it are added after s's own
//! product has written it (beta = 0), so it is never zero-filled: that fill was a visible part of the
//! extend-add time. Mapped update matrices come zeroed from the kernel anyway: they take the children whole
//! first, so that the largest children's matrices are not kept any longer.
bool FrontFactorization::factor_supernode(const MatrixChunk& M, int s, Workspace& ws) {
  const int nr = S_.nrows(s) - S_.ncols(s);
  const FactorBlock L = block(s);
  const int* kids = S_.child.data() + S_.cptr[std::size_t(s)];
  const int nkids = S_.cptr[std::size_t(s) + 1] - S_.cptr[std::size_t(s)];
  // Not begun by children assembled early (top supernodes), and not mapped.
  const bool fresh_heap = nr > 0 && !updates_[std::size_t(s)] && !UpdateBlock::mapped(nr);
  for (int q = 0; q < nkids; ++q)
    if (updates_[std::size_t(kids[q])]) assemble_child(kids[q], s, ws, fresh_heap ? kPivot : kBoth);
  add_matrix_entries(M, s, L, ws);
  if (!factor_panels(s, L, ws)) return false;
  if (nr > 0) {
    form_update(s, L, fresh_heap);
    if (fresh_heap)
      for (int q = 0; q < nkids; ++q)
        if (updates_[std::size_t(kids[q])]) assemble_child(kids[q], s, ws, kUpdate);
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
bool FrontFactorization::factor_panels(int s, const FactorBlock& L, Workspace& ws) {
  const int f = S_.col0[std::size_t(s)];
  const int K = FactorBlock::kWidth;
  double* D = ws.diag.data();
  for (int q = 0; q < L.panels(); ++q) {
    const int c0 = L.c0(q), w = L.width(q), h = L.height(q);
    double* T = L.tri(q);
    for (int j = 0; j < w; ++j)
      std::copy(T + packed_column(j, w), T + packed_column(j + 1, w), D + std::size_t(j) * std::size_t(w + 1));
    for (int p = 0; p < q; ++p) {
      const double* Rp = L.rect(p) + (c0 - L.c0(p) - K);  // panel p's rows from c0 down
      const int ldp = L.height(p);
      cblas_dsyrk(CblasColMajor, CblasLower, CblasNoTrans, w, K, -1.0, Rp, ldp, 1.0, D, w);
      if (h > 0)
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, h, w, K, -1.0, Rp + w, ldp, Rp, ldp, 1.0, L.rect(q), h);
    }
    int info = 0;
    LAPACK_dpotrf("L", &w, D, &w, &info);
    if (info != 0) {
      std::int64_t expected = -1;
      failed_column_.compare_exchange_strong(expected, std::int64_t(f + c0 + std::max(info, 1) - 1));
      return false;
    }
    if (h > 0) cblas_dtrsm(CblasColMajor, CblasRight, CblasLower, CblasTrans, CblasNonUnit, h, w, 1.0, D, w, L.rect(q), h);
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
//! is written by the first panel's product (beta = 0).
void FrontFactorization::form_update(int s, const FactorBlock& L, bool fresh_heap) {
  const int nc = S_.ncols(s), nr = S_.nrows(s) - nc;
  UpdateBlock U = updates_[std::size_t(s)] ? std::move(updates_[std::size_t(s)]) : UpdateBlock(nr, !fresh_heap, &pool_);
  for (int p = 0; p < L.panels(); ++p) {
    const int wp = L.width(p), ldp = L.height(p);
    const double* B = L.rect(p) + (nc - L.c0(p) - wp);
    const double beta = fresh_heap && p == 0 ? 0.0 : 1.0;
    for (int u = 0; u < U.panels(); ++u) {
      const int u0 = u * UpdateBlock::kWidth, wu = U.width(u), ldu = nr - u0, below = ldu - wu;
      cblas_dsyrk(CblasColMajor, CblasLower, CblasNoTrans, wu, wp, -1.0, B + u0, ldp, beta, U.panel(u), ldu);
      if (below > 0)
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, below, wu, wp, -1.0, B + u0 + wu, ldp, B + u0, ldp, beta,
                    U.panel(u) + wu, ldu);
    }
  }
  updates_[std::size_t(s)] = std::move(U);
}

}  // namespace db::multifrontal
