// Structured build (thesis 2.4.2): the upper triangle of A^T A is laid out from the adjacency (two vertices
// interact when they share a 1-ring, i.e. are at most two edges apart) and filled row block by row block,
// so A itself is never stored. TF uses the same vertex pattern expanded to 3x3 blocks.
#include <algorithm>

#include "systems/build_detail.h"

namespace db::detail {
namespace {

// Block (vertex-level) CSC pattern of K's upper triangle, columns and rows in unknown numbering.
struct BlockPattern {
  std::vector<int> colptr, rows;  // rows sorted ascending per column; the diagonal is last
  int find(int col, int row) const {
    const int* b = rows.data() + colptr[col];
    const int* e = rows.data() + colptr[col + 1];
    return static_cast<int>(std::lower_bound(b, e, row) - rows.data());
  }
};

BlockPattern block_pattern(const Adjacency& adj, const Unknowns& unk) {
  const int nu = unk.num_unknowns();
  BlockPattern p;
  p.colptr.assign(nu + 1, 0);
  p.rows.reserve(static_cast<std::size_t>(nu) * 12);
  std::vector<int> mark(nu, -1);
  std::vector<int> col;
  for (int ku = 0; ku < nu; ++ku) {
    const int k = unk.unknown_vertices[ku];
    col.clear();
    auto visit = [&](int j) {
      const int ju = unk.unknown_of[j];
      if (ju < 0 || ju > ku || mark[ju] == ku) return;
      mark[ju] = ku;
      col.push_back(ju);
    };
    visit(k);
    for (const int* a = adj.begin(k); a != adj.end(k); ++a) {
      visit(*a);
      for (const int* c = adj.begin(*a); c != adj.end(*a); ++c) visit(*c);
    }
    std::sort(col.begin(), col.end());
    p.rows.insert(p.rows.end(), col.begin(), col.end());
    p.colptr[ku + 1] = static_cast<int>(p.rows.size());
  }
  return p;
}

// Scalar CSC of the upper triangle: block column k expands to b columns; off-diagonal blocks contribute
// b rows each, the diagonal block only its upper part. Entry (b*j + c1, b*k + c2) then sits at
// colptr[b*k + c2] + b * (position of j in block column k) + c1.
SpMat expand_pattern(const BlockPattern& p, int b) {
  const int nu = static_cast<int>(p.colptr.size()) - 1;
  const int n = b * nu;
  SpMat K(n, n);
  std::vector<int> colptr(n + 1, 0);
  for (int k = 0; k < nu; ++k) {
    const int nb = p.colptr[k + 1] - p.colptr[k];  // includes the diagonal block
    for (int c2 = 0; c2 < b; ++c2) colptr[b * k + c2 + 1] = colptr[b * k + c2] + b * (nb - 1) + c2 + 1;
  }
  const int nnz = colptr[n];
  K.resizeNonZeros(nnz);
  std::copy(colptr.begin(), colptr.end(), K.outerIndexPtr());
  int* ri = K.innerIndexPtr();
  for (int k = 0; k < nu; ++k) {
    for (int c2 = 0; c2 < b; ++c2) {
      int pos = colptr[b * k + c2];
      for (int t = p.colptr[k]; t < p.colptr[k + 1]; ++t) {
        const int j = p.rows[t];
        const int upto = (j == k) ? c2 + 1 : b;
        for (int c1 = 0; c1 < upto; ++c1) ri[pos++] = b * j + c1;
      }
    }
  }
  std::fill(K.valuePtr(), K.valuePtr() + nnz, 0.0);
  return K;
}

}  // namespace

NormalSystem build_structured(const EnergyOperator& op, const Unknowns& unk) {
  const Adjacency& adj = op.adjacency();
  const int n = op.num_vertices(), b = op.block(), r = op.rhs_cols(), b2 = b * b;
  NormalSystem sys;
  const BlockPattern pat = block_pattern(adj, unk);
  sys.K = expand_pattern(pat, b);
  double* Kv = sys.K.valuePtr();
  const int* Kp = sys.K.outerIndexPtr();
  sys.g0 = DenseMat::Zero(static_cast<Eigen::Index>(b) * unk.num_unknowns(), r);

  std::vector<Eigen::Triplet<double, int>> ctrip;  // coupling to hard vertices: a thin band around them
  std::vector<int> cols;
  std::vector<double> coeffs;
  double blk[9], tgt[3];
  for (int i = 0; i < n; ++i) {
    op.row(i, cols, coeffs);
    if (!row_active(cols, unk)) continue;
    op.target(i, tgt);
    const int m = static_cast<int>(cols.size());
    for (int a = 0; a < m; ++a) {
      const int ju = unk.unknown_of[cols[a]];
      if (ju < 0) continue;
      const double* Ca = coeffs.data() + b2 * a;
      for (int c1 = 0; c1 < b; ++c1)  // g0 += C_ia^T target_i
        for (int col = 0; col < r; ++col) {
          double s = 0;
          for (int rr = 0; rr < b; ++rr) s += Ca[rr * b + c1] * tgt[rr * r + col];
          sys.g0(b * ju + c1, col) += s;
        }
      for (int c = 0; c < m; ++c) {
        const int k = cols[c];
        const int ku = unk.unknown_of[k];
        if (ku >= 0 && ku < ju) continue;  // upper triangle only: row block ju <= column block ku
        block_AtB(b, Ca, coeffs.data() + b2 * c, blk);
        if (ku >= 0) {
          const int t = pat.find(ku, ju) - pat.colptr[ku];
          for (int c2 = 0; c2 < b; ++c2) {
            const int base = Kp[b * ku + c2] + b * t;
            const int upto = (ju == ku) ? c2 + 1 : b;
            for (int c1 = 0; c1 < upto; ++c1) Kv[base + c1] += blk[c1 * b + c2];
          }
        } else {
          const int kh = unk.hard_of[k];
          for (int c1 = 0; c1 < b; ++c1)
            for (int c2 = 0; c2 < b; ++c2) ctrip.emplace_back(b * ju + c1, b * kh + c2, blk[c1 * b + c2]);
        }
      }
    }
  }
  const double w2 = unk.soft_weight * unk.soft_weight;
  for (int v : unk.soft_vertices) {
    const int ku = unk.unknown_of[v];
    const int t = pat.find(ku, ku) - pat.colptr[ku];
    for (int c = 0; c < b; ++c) Kv[Kp[b * ku + c] + b * t + c] += w2;
  }
  sys.C.resize(static_cast<Eigen::Index>(b) * unk.num_unknowns(), static_cast<Eigen::Index>(b) * unk.num_hard());
  sys.C.setFromTriplets(ctrip.begin(), ctrip.end());
  sys.held_bytes = {{"K_upper", sparse_bytes(sys.K)}, {"C", sparse_bytes(sys.C)},
                    {"g0", static_cast<std::size_t>(sys.g0.size()) * sizeof(double)}};
  return sys;
}

}  // namespace db::detail
