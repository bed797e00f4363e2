#include "solvers/multifrontal/symbolic.h"

#include <algorithm>
#include <cstdint>
#include <memory>
#include <numeric>

#include <cholmod.h>
#include <fmt/format.h>

#include "solvers/base/error.h"
#include "solvers/base/resources.h"
#include "solvers/multifrontal/storage.h"
#include "solvers/ordering/cholmod_views.h"
#include "solvers/ordering/graph_ordering.h"

namespace db::multifrontal {

double supernode_flops(const Symbolic& S, int s) {
  double f = 0;
  const int m = S.nrows(s);
  for (int k = 0; k < S.ncols(s); ++k) f += double(m - k) * double(m - k);
  return f;
}

const char* default_ordering(int b) { return b > 1 ? "metis" : "amd"; }

namespace {

//! Threads for a loop over `work` units (entries of a pattern, rows of a factor): the worker threads, one per
//! kGrain units at most. Why: below a few hundred thousand units a thread's start costs more than its share.
int loop_threads(std::size_t work) {
  constexpr std::size_t kGrain = std::size_t(1) << 19;
  return int(std::min<std::size_t>(std::size_t(std::max(worker_threads(), 1)), work / kGrain + 1));
}

//! Upper triangle of the block graph with the diagonal, the pattern CHOLMOD analyzes, into Up / Ui; a scalar
//! matrix (b = 1) is its own block graph and is viewed in place. Ranges of block columns on threads, concatenated
//! in order: the same arrays for any thread count.
GraphPattern block_pattern(const SpMat& upper, int b, std::vector<int>& Up, std::vector<int>& Ui) {
  const int nb = int(upper.cols()) / b;
  if (b == 1) return GraphPattern{nb, upper.outerIndexPtr(), upper.innerIndexPtr()};
  const int* Ap = upper.outerIndexPtr();
  const int* Ai = upper.innerIndexPtr();
  Up.assign(std::size_t(nb) + 1, 0);
  const int T = loop_threads(std::size_t(upper.nonZeros()));
  std::vector<std::vector<int>> part(static_cast<std::size_t>(T));
  run_tasks(T, [&](int t) {
    const int lo = int(std::int64_t(nb) * t / T), hi = int(std::int64_t(nb) * (t + 1) / T);
    std::vector<int>& out = part[std::size_t(t)];
    out.reserve(std::size_t(Ap[hi * b] - Ap[lo * b]) / std::size_t(b * b) + std::size_t(hi - lo));
    std::vector<int> mark(std::size_t(nb), -1);
    for (int J = lo; J < hi; ++J) {
      const std::size_t start = out.size();
      mark[std::size_t(J)] = J;  // the diagonal block, appended last
      for (int j = J * b; j < (J + 1) * b; ++j)
        for (int p = Ap[j]; p < Ap[j + 1]; ++p)
          if (const int I = Ai[p] / b; I < J && mark[std::size_t(I)] != J) {
            mark[std::size_t(I)] = J;
            out.push_back(I);
          }
      std::sort(out.begin() + std::ptrdiff_t(start), out.end());
      out.push_back(J);
      Up[std::size_t(J) + 1] = int(out.size() - start);
    }
  });
  std::partial_sum(Up.begin(), Up.end(), Up.begin());
  Ui.resize(std::size_t(Up[std::size_t(nb)]));
  std::size_t at = 0;
  for (const std::vector<int>& out : part) {
    std::copy(out.begin(), out.end(), Ui.begin() + std::ptrdiff_t(at));
    at += out.size();
  }
  return GraphPattern{nb, Up.data(), Ui.data()};
}

//! Frees a CHOLMOD factor with the common it was made with.
struct FactorFree {
  cholmod_common* cc;
  void operator()(cholmod_factor* L) const { cholmod_free_factor(&L, cc); }
};
using FactorPtr = std::unique_ptr<cholmod_factor, FactorFree>;

//! Permutation and supernodes of the block factor L expanded to b x b blocks: perm, col0, rptr, rows, xptr,
//! nnz, parent. The rows are expanded and sorted on threads, in ranges of supernodes of about equal rows.
void expand_supernodes(const cholmod_factor& L, int b, Symbolic& S) {
  const int nb = int(L.n), ns = int(L.nsuper);
  const int* Perm = static_cast<const int*>(L.Perm);
  const int* super = static_cast<const int*>(L.super);
  const int* pi = static_cast<const int*>(L.pi);
  const int* srow = static_cast<const int*>(L.s);
  S.n = nb * b;
  bool identity = true;
  for (int k = 0; k < nb; ++k) identity = identity && Perm[k] == k;
  if (!identity) {
    S.perm.resize(std::size_t(S.n));
    for (int k = 0; k < nb; ++k)
      for (int c = 0; c < b; ++c) S.perm[std::size_t(b * k + c)] = b * Perm[k] + c;
  }
  S.col0.resize(std::size_t(ns) + 1);
  S.rptr.assign(std::size_t(ns) + 1, 0);
  S.xptr.assign(std::size_t(ns) + 1, 0);
  std::vector<int> super_of(static_cast<std::size_t>(nb));
  for (int s = 0; s < ns; ++s) {
    S.col0[std::size_t(s)] = b * super[s];
    for (int J = super[s]; J < super[s + 1]; ++J) super_of[std::size_t(J)] = s;
    const int m = b * (pi[s + 1] - pi[s]), nc = b * (super[s + 1] - super[s]);
    S.rptr[std::size_t(s) + 1] = S.rptr[std::size_t(s)] + m;
    S.xptr[std::size_t(s) + 1] = S.xptr[std::size_t(s)] + FactorBlock::size(m, nc);
  }
  S.col0[std::size_t(ns)] = S.n;
  S.nnz = S.xptr[std::size_t(ns)];
  S.rows.resize(std::size_t(S.rptr[std::size_t(ns)]));
  const int T = loop_threads(S.rows.size());
  run_tasks(T, [&](int t) {
    // Supernodes whose rows start in this thread's share of all rows.
    const auto from = [&](int k) {
      const std::int64_t at = std::int64_t(S.rows.size()) * k / T;
      return int(std::lower_bound(S.rptr.begin(), S.rptr.end() - 1, at) - S.rptr.begin());
    };
    for (int s = from(t), end = from(t + 1); s < end; ++s) {
      int* out = S.rows.data() + S.rptr[std::size_t(s)];
      for (int p = pi[s]; p < pi[s + 1]; ++p)
        for (int c = 0; c < b; ++c) *out++ = b * srow[p] + c;
      // CHOLMOD lists a supernode's own columns first but leaves the rows below unsorted; the extend-add
      // relies on ascending rows (it maps a child's lower triangle into the parent's lower triangle).
      std::sort(S.rows.data() + S.rptr[std::size_t(s)], out);
    }
  });
  S.parent.assign(std::size_t(ns), -1);
  for (int s = 0; s < ns; ++s) {
    const int nsc = super[s + 1] - super[s];
    if (pi[s + 1] - pi[s] > nsc)
      S.parent[std::size_t(s)] = super_of[std::size_t(S.rows[std::size_t(S.rptr[std::size_t(s)] + b * nsc)] / b)];
  }
}

//! Children lists and subtree ranges from S.parent, and the flop count. \throw SolverError unless postordered.
void link_tree(Symbolic& S) {
  const int ns = S.nsuper();
  S.cptr.assign(std::size_t(ns) + 1, 0);
  for (int s = 0; s < ns; ++s)
    if (S.parent[std::size_t(s)] >= 0) ++S.cptr[std::size_t(S.parent[std::size_t(s)]) + 1];
  for (int s = 0; s < ns; ++s) S.cptr[std::size_t(s) + 1] += S.cptr[std::size_t(s)];
  S.child.resize(std::size_t(S.cptr[std::size_t(ns)]));
  std::vector<int> next(S.cptr.begin(), S.cptr.end() - 1);
  S.first.resize(std::size_t(ns));
  std::iota(S.first.begin(), S.first.end(), 0);
  for (int s = 0; s < ns; ++s) {
    const int p = S.parent[std::size_t(s)];
    if (p < 0) continue;
    if (p <= s) throw SolverError("multifrontal: the supernodal tree is not postordered");
    S.child[std::size_t(next[std::size_t(p)]++)] = s;
    S.first[std::size_t(p)] = std::min(S.first[std::size_t(p)], S.first[std::size_t(s)]);
  }
  for (int s = 0; s < ns; ++s) S.flops += supernode_flops(S, s);
}

//! CHOLMOD's supernodal analysis of G in its own order from its elimination tree and column counts: a simplicial
//! symbolic factor holding the counts, handed to cholmod_super_symbolic with the tree, as cholmod_analyze does after
//! its own pass.
FactorPtr super_symbolic_given(const GraphPattern& G, const EliminationTree& tree, cholmod_common& cc) {
  FactorPtr L(cholmod_allocate_factor(std::size_t(G.n), &cc), FactorFree{&cc});
  if (!L || cc.status < CHOLMOD_OK)
    throw SolverError(fmt::format("multifrontal: no symbolic factor of {} columns, CHOLMOD status {}", G.n, cc.status));
  std::copy(tree.count.begin(), tree.count.end(), static_cast<int*>(L->ColCount));
  std::vector<int> parent = tree.parent;  // CHOLMOD takes it as int*
  cholmod_sparse A = cholmod_upper_view(std::size_t(G.n), G.colptr, G.rows, nullptr);
  if (!cholmod_super_symbolic(&A, nullptr, parent.data(), L.get(), &cc) || cc.status < CHOLMOD_OK)
    throw SolverError(fmt::format("multifrontal: CHOLMOD's supernodal analysis of the given tree failed, status {}",
                                  cc.status));
  return L;
}

//! A tree's first descendant of each node (itself at a leaf), from a forest whose parents are later than their
//! children. \throw SolverError at a parent that is not, or at a subtree that is not contiguous.
std::vector<int> first_descendants(const std::vector<int>& parent) {
  const int n = int(parent.size());
  std::vector<int> first(static_cast<std::size_t>(n)), size(static_cast<std::size_t>(n), 1);
  std::iota(first.begin(), first.end(), 0);
  for (int j = 0; j < n; ++j) {
    if (j - first[std::size_t(j)] + 1 != size[std::size_t(j)])
      throw SolverError(fmt::format("multifrontal: the given elimination tree is not postordered at node {}", j));
    const int p = parent[std::size_t(j)];
    if (p < 0) continue;
    if (p <= j || p >= n)
      throw SolverError(
          fmt::format("multifrontal: the given elimination tree has parent {} for node {} of {}", p, j, n));
    first[std::size_t(p)] = std::min(first[std::size_t(p)], first[std::size_t(j)]);
    size[std::size_t(p)] += size[std::size_t(j)];
  }
  return first;
}

//! Checks each count of `tree` against its place in the tree (check_tree). \throw SolverError at the first misfit.
void check_counts(const EliminationTree& tree) {
  const int n = int(tree.parent.size());
  for (int j = 0; j < n; ++j) {
    const int c = tree.count[std::size_t(j)], p = tree.parent[std::size_t(j)];
    const bool fits = p < 0 ? c == 1 : c >= 2 && c <= n - j && c - 1 <= tree.count[std::size_t(p)];
    if (!fits)
      throw SolverError(
          fmt::format("multifrontal: the given column count {} of column {} does not fit its tree", c, j));
  }
}

}  // namespace

void check_tree(const EliminationTree& tree, int n, const int* colptr, const int* rows) {
  if (int(tree.parent.size()) != n || int(tree.count.size()) != n || tree.upper_entries != std::size_t(colptr[n]))
    throw SolverError(fmt::format("multifrontal: the given elimination tree ({} nodes, {} graph entries) is not of "
                                  "this matrix's {}-vertex graph of {} entries",
                                  tree.parent.size(), tree.upper_entries, n, colptr[n]));
  const std::vector<int> first = first_descendants(tree.parent);
  check_counts(tree);
  const int T = loop_threads(std::size_t(colptr[n]));
  std::vector<int> misfit(static_cast<std::size_t>(T), -1);  // a column per range whose edge leaves its subtree
  run_tasks(T, [&](int t) {
    const int lo = int(std::int64_t(n) * t / T), hi = int(std::int64_t(n) * (t + 1) / T);
    for (int j = lo; j < hi && misfit[std::size_t(t)] < 0; ++j)
      if (colptr[j + 1] > colptr[j] && rows[colptr[j]] < first[std::size_t(j)]) misfit[std::size_t(t)] = j;
  });
  for (const int j : misfit)
    if (j >= 0)
      throw SolverError(fmt::format("multifrontal: column {} of the matrix has an entry outside its subtree in the "
                                    "given elimination tree", j));
}

Symbolic analyze_blocks(const SpMat& upper, int b, const std::string& method, const EliminationTree* tree) {
  std::vector<int> Up, Ui;
  const GraphPattern G = block_pattern(upper, b, Up, Ui);
  const bool given = tree && method == "natural";
  if (given) check_tree(*tree, G.n, G.colptr, G.rows);
  cholmod_common cc;
  cholmod_start(&cc);
  std::unique_ptr<cholmod_common, int (*)(cholmod_common*)> finish(&cc, cholmod_finish);
  cc.print = 0;
  cc.supernodal = CHOLMOD_SUPERNODAL;
  // CHOLMOD's amalgamation thresholds count columns; a block column is b scalar columns.
  for (int k = 0; k < 3; ++k) cc.nrelax[k] = std::max<std::size_t>(1, (cc.nrelax[k] + std::size_t(b) - 1) / std::size_t(b));
  // The shared graph analysis: METIS on large graphs runs dissected on two threads (solvers/ordering).
  FactorPtr L = given ? super_symbolic_given(G, *tree, cc)
                      : FactorPtr(analyze_graph(G, method == "default" ? default_ordering(b) : method, cc),
                                  FactorFree{&cc});
  if (!L->is_super)
    throw SolverError(fmt::format("multifrontal: the symbolic analysis of the {0}x{0} block graph is not supernodal",
                                  G.n));
  Symbolic S;
  expand_supernodes(*L, b, S);
  L.reset();
  link_tree(S);
  return S;
}

}  // namespace db::multifrontal
