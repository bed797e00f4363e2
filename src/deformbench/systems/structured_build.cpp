// Structured build (thesis 2.4.2): the upper triangle of A^T A is laid out from the adjacency (two vertices
// interact when they share a 1-ring, i.e. are at most two edges apart) and filled row block by row block,
// so A itself is never stored. TF uses the same vertex pattern expanded to 3x3 blocks. A rank share builds a
// range of block columns only, as the threads do (each generates the row blocks that touch its columns).
#include <algorithm>

#include "solvers/base/resources.h"
#include "systems/build_detail.h"

namespace db::detail {
namespace {

using Trip = Eigen::Triplet<double, int>;

// Column ranges of the threads: contiguous ranges of the block columns [first, last), balanced by stored blocks.
std::vector<int> column_split(const InteractionPattern& pat, int first, int last, int T) {
  std::vector<int> split(T + 1, last);
  split[0] = first;
  const long long base = pat.colptr[first], stored = pat.colptr[last] - base;
  for (int t = 1, k = first; t < T; ++t) {
    const long long target = base + stored * t / T;
    while (k < last && pat.colptr[k] < target) ++k;
    split[t] = k;
  }
  return split;
}

// One thread's share of the structured build: the entries of K in block columns [lo, hi), the rows of g0 and C
// of those unknowns. The block size is a template parameter so the 3x3 block products and scatters unroll.
template <int B>
class ColumnRangeFill {
 public:
  static constexpr int b = B, b2 = B * B, r = 3 / B;

  ColumnRangeFill(const EnergyOperator& op, const Unknowns& unk, const InteractionPattern& pat, NormalSystem& sys,
                  int lo, int hi)
      : op_(op), unk_(unk), pat_(pat), Kv_(sys.K.valuePtr()), Kp_(sys.K.outerIndexPtr()), g0_(sys.g0), lo_(lo),
        hi_(hi) {}

  //! Generates every row block in `row_order` that touches the range and adds its products.
  void run(const std::vector<int>& row_order, std::vector<Trip>& ctrip) {
    const Adjacency& adj = op_.adjacency();
    for (int i : row_order) {
      bool touches = mine(i);
      for (const int* q = adj.begin(i); q != adj.end(i) && !touches; ++q) touches = mine(*q);
      if (!touches) continue;
      op_.row(i, cols_, coeffs_);
      op_.target(i, tgt_);
      add_row_block(ctrip);
    }
  }

 private:
  const EnergyOperator& op_;
  const Unknowns& unk_;
  const InteractionPattern& pat_;
  double* Kv_;
  const int* Kp_;
  DenseMat& g0_;
  const int lo_, hi_;
  std::vector<int> cols_;
  std::vector<double> coeffs_;
  double blk_[9], tgt_[3];

  bool mine(int v) const {
    const int u = unk_.unknown_of[v];
    return u >= lo_ && u < hi_;
  }

  // The row block in cols_, coeffs_, tgt_: C_ia^T target into g0, C_ia^T C_ic into K (upper triangle, this
  // range's columns) or C (this range's rows).
  void add_row_block(std::vector<Trip>& ctrip) {
    const bool has_target = tgt_[0] != 0 || tgt_[1] != 0 || tgt_[2] != 0;
    const int m = static_cast<int>(cols_.size());
    for (int a = 0; a < m; ++a) {
      const int ju = unk_.unknown_of[cols_[a]];
      if (ju < 0) continue;
      const double* Ca = coeffs_.data() + b2 * a;
      const bool own_row = ju >= lo_ && ju < hi_;
      if (own_row && has_target) add_target(ju, Ca);
      for (int c = 0; c < m; ++c) {
        const int k = cols_[c];
        const int ku = unk_.unknown_of[k];
        if (ku >= 0) {
          // Upper triangle only (row block ju <= column block ku), and only the columns this thread owns.
          if (ku < ju || ku < lo_ || ku >= hi_) continue;
          block_AtB<B>(Ca, coeffs_.data() + b2 * c, blk_);
          add_K(ju, ku);
        } else if (own_row) {
          block_AtB<B>(Ca, coeffs_.data() + b2 * c, blk_);
          const int kh = unk_.hard_of[k];
          for (int c1 = 0; c1 < b; ++c1)
            for (int c2 = 0; c2 < b; ++c2) ctrip.emplace_back(b * ju + c1, b * kh + c2, blk_[c1 * b + c2]);
        }
      }
    }
  }

  // g0 += C_ia^T target_i.
  void add_target(int ju, const double* Ca) {
    for (int c1 = 0; c1 < b; ++c1)
      for (int col = 0; col < r; ++col) {
        double s = 0;
        for (int rr = 0; rr < b; ++rr) s += Ca[rr * b + c1] * tgt_[rr * r + col];
        g0_(b * ju + c1, col) += s;
      }
  }

  // K's block (ju, ku) += blk_.
  void add_K(int ju, int ku) {
    const int pos = pat_.find(ku, ju) - pat_.colptr[ku];
    for (int c2 = 0; c2 < b; ++c2) {
      const int base = Kp_[b * ku + c2] + b * pos;
      const int upto = (ju == ku) ? c2 + 1 : b;
      for (int c1 = 0; c1 < upto; ++c1) Kv_[base + c1] += blk_[c1 * b + c2];
    }
  }
};

template <int B>
NormalSystem build_structured_blocks(const EnergyOperator& op, const Unknowns& unk, const InteractionPattern* given,
                                     int threads, int first, int last) {
  constexpr int b = B, r = 3 / B;
  const int nu = unk.num_unknowns();
  NormalSystem sys;
  InteractionPattern own;
  if (!given) own = interaction_pattern(op.adjacency(), unk, 2, first, last);
  const InteractionPattern& pat = given ? *given : own;
  expand_upper(pat, b).swap(sys.K);  // not an assignment: Eigen 3.4 copies a returned SparseMatrix
  sys.g0 = DenseMat::Zero(static_cast<Eigen::Index>(b) * nu, r);

  // Threads own contiguous ranges of block columns and fill only those, so no two threads write the same entry.
  // A row block touching two ranges is generated by both: with the unknowns in a nested-dissection order that
  // is a thin boundary.
  const int T = std::max(1, std::min(threads > 0 ? threads : worker_threads(), (last - first) / 256 + 1));
  const std::vector<int> split = column_split(pat, first, last, T);
  std::vector<std::vector<Trip>> ctrip(T);  // coupling to hard vertices: a thin band
  // Row blocks in the unknowns' order, then the hard vertices': consecutive rows then write neighbouring
  // columns of K (the unknowns are in a nested-dissection order), where the vertex order of a subdivided mesh
  // jumps across the whole matrix.
  std::vector<int> row_order(unk.unknown_vertices);
  row_order.insert(row_order.end(), unk.hard_vertices.begin(), unk.hard_vertices.end());
  run_tasks(T, [&](int t) {
    ColumnRangeFill<B>(op, unk, pat, sys, split[t], split[t + 1]).run(row_order, ctrip[t]);
  });

  double* Kv = sys.K.valuePtr();
  const int* Kp = sys.K.outerIndexPtr();
  const double w2 = unk.soft_weight * unk.soft_weight;
  for (int v : unk.soft_vertices) {
    const int ku = unk.unknown_of[v];
    if (ku < first || ku >= last) continue;  // another share's
    const int pos = pat.find(ku, ku) - pat.colptr[ku];
    for (int c = 0; c < b; ++c) Kv[Kp[b * ku + c] + b * pos + c] += w2;
  }
  for (int t = 1; t < T; ++t) ctrip[0].insert(ctrip[0].end(), ctrip[t].begin(), ctrip[t].end());
  sys.C.resize(static_cast<Eigen::Index>(b) * nu, static_cast<Eigen::Index>(b) * unk.num_hard());
  sys.C.setFromTriplets(ctrip[0].begin(), ctrip[0].end());
  if (first == 0 && last == nu) sys.tree = unk.tree;  // K's block graph is the 2-ring graph the tree is of
  sys.held_bytes = {{"K_upper", sparse_bytes(sys.K)}, {"C", sparse_bytes(sys.C)},
                    {"g0", static_cast<std::size_t>(sys.g0.size()) * sizeof(double)}};
  return sys;
}

}  // namespace

NormalSystem build_structured(const EnergyOperator& op, const Unknowns& unk, const InteractionPattern* pattern,
                              int threads, int first, int last) {
  if (last < 0) last = unk.num_unknowns();
  return op.block() == 1 ? build_structured_blocks<1>(op, unk, pattern, threads, first, last)
                         : build_structured_blocks<3>(op, unk, pattern, threads, first, last);
}

}  // namespace db::detail
