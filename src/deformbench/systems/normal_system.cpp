#include "systems/normal_system.h"

#include <algorithm>
#include <mutex>

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "solvers/base/resources.h"
#include "core/timer.h"
#include "systems/build_detail.h"

namespace db {

const EnumText<Build>& enum_text(Build) {
  static const EnumText<Build> t{"build", {{Build::Dense, "dense"}, {Build::Naive, "naive"}, {Build::Structured, "structured"}}};
  return t;
}

Unknowns make_unknowns(const std::vector<Constraint>& kind, double soft_weight) {
  Unknowns u;
  const int n = static_cast<int>(kind.size());
  u.unknown_of.assign(n, -1);
  u.hard_of.assign(n, -1);
  u.soft_weight = soft_weight;
  for (int v = 0; v < n; ++v) {
    if (kind[v] == Constraint::Hard) {
      u.hard_of[v] = static_cast<int>(u.hard_vertices.size());
      u.hard_vertices.push_back(v);
    } else {
      u.unknown_of[v] = static_cast<int>(u.unknown_vertices.size());
      u.unknown_vertices.push_back(v);
      if (kind[v] == Constraint::Soft) u.soft_vertices.push_back(v);
    }
  }
  return u;
}

int InteractionPattern::find(int col, int row) const {
  const int* b = rows.data() + colptr[col];
  const int* e = rows.data() + colptr[col + 1];
  return static_cast<int>(std::lower_bound(b, e, row) - rows.data());
}

InteractionPattern interaction_pattern(const Adjacency& adj, const Unknowns& unk, int rings, int first, int last) {
  const int nu = unk.num_unknowns();
  if (last < 0) last = nu;
  const int span = last - first;
  // Column ranges on the worker threads, concatenated afterwards: the pattern is computed once for the
  // vertex ordering and once for the build, a visible share of the build on large meshes.
  const int T = std::max(1, std::min(worker_threads(), span / 8192 + 1));
  std::vector<std::vector<int>> rows(T), counts(T);
  auto work = [&](int t) {
    const int lo = first + static_cast<int>(static_cast<long long>(span) * t / T);
    const int hi = first + static_cast<int>(static_cast<long long>(span) * (t + 1) / T);
    std::vector<int>& out = rows[t];
    std::vector<int>& cnt = counts[t];
    out.reserve(static_cast<std::size_t>(hi - lo) * 12);
    cnt.reserve(static_cast<std::size_t>(hi - lo));
    std::vector<int> mark(nu, -1);
    for (int ku = lo; ku < hi; ++ku) {
      const int k = unk.unknown_vertices[ku];
      const std::size_t start = out.size();
      auto visit = [&](int j) {
        const int ju = unk.unknown_of[j];
        if (ju < 0 || ju > ku || mark[ju] == ku) return;
        mark[ju] = ku;
        out.push_back(ju);
      };
      visit(k);
      for (const int* a = adj.begin(k); a != adj.end(k); ++a) {
        visit(*a);
        if (rings > 1)
          for (const int* c = adj.begin(*a); c != adj.end(*a); ++c) visit(*c);
      }
      std::sort(out.begin() + static_cast<std::ptrdiff_t>(start), out.end());
      cnt.push_back(static_cast<int>(out.size() - start));
    }
  };
  run_tasks(T, work);
  InteractionPattern p;
  p.colptr.assign(nu + 1, 0);
  std::vector<std::size_t> at(T + 1, 0);  // where each range's rows go
  for (int t = 0; t < T; ++t) at[t + 1] = at[t] + rows[t].size();
  p.rows.resize(at[T]);
  int ku = first;
  for (int t = 0; t < T; ++t)
    for (int c : counts[t]) {
      p.colptr[ku + 1] = p.colptr[ku] + c;
      ++ku;
    }
  // The copy on the threads too: on large meshes it is a visible share of the pattern's time on many cores.
  run_tasks(T, [&](int t) {
    std::copy(rows[t].begin(), rows[t].end(), p.rows.begin() + static_cast<std::ptrdiff_t>(at[t]));
    std::vector<int>().swap(rows[t]);
  });
  std::fill(p.colptr.begin() + last + 1, p.colptr.end(), p.colptr[last]);  // empty columns after the range
  return p;
}

SpMat expand_upper(const InteractionPattern& p, int b) {
  const int nu = static_cast<int>(p.colptr.size()) - 1;
  const int n = b * nu;
  SpMat K(n, n);
  std::vector<int> colptr(n + 1, 0);
  for (int k = 0; k < nu; ++k) {
    const int nb = p.colptr[k + 1] - p.colptr[k];  // includes the diagonal block; 0: a column outside a share
    for (int c2 = 0; c2 < b; ++c2) colptr[b * k + c2 + 1] = colptr[b * k + c2] + (nb > 0 ? b * (nb - 1) + c2 + 1 : 0);
  }
  const int nnz = colptr[n];
  K.resizeNonZeros(nnz);
  std::copy(colptr.begin(), colptr.end(), K.outerIndexPtr());
  int* ri = K.innerIndexPtr();
  double* val = K.valuePtr();
  advise_huge_pages(ri, std::size_t(nnz) * sizeof(int));
  advise_huge_pages(val, std::size_t(nnz) * sizeof(double));
  // Row indices and zero values written by column ranges on the worker threads: K is the build's largest array,
  // and writing it is mostly first-touch page faults, which parallelize.
  run_ranges(nu, 4096, [&](int k0, int k1) {
    for (int k = k0; k < k1; ++k)
      for (int c2 = 0; c2 < b; ++c2) {
        int pos = colptr[b * k + c2];
        std::fill(val + pos, val + colptr[b * k + c2 + 1], 0.0);
        for (int t = p.colptr[k]; t < p.colptr[k + 1]; ++t) {
          const int j = p.rows[t];
          const int upto = (j == k) ? c2 + 1 : b;
          for (int c1 = 0; c1 < upto; ++c1) ri[pos++] = b * j + c1;
        }
      }
  });
  return K;
}

std::size_t sparse_bytes(const SpMat& m) {
  return static_cast<std::size_t>(m.nonZeros()) * (sizeof(double) + sizeof(int)) +
         static_cast<std::size_t>(m.outerSize() + 1) * sizeof(int);
}

NormalSystem::NormalSystem(NormalSystem&& o) noexcept { *this = std::move(o); }

NormalSystem& NormalSystem::operator=(NormalSystem&& o) noexcept {
  build = o.build;
  block = o.block;
  rhs_cols = o.rhs_cols;
  K.swap(o.K);
  C.swap(o.C);
  K_dense = std::move(o.K_dense);
  C_dense = std::move(o.C_dense);
  g0 = std::move(o.g0);
  At.swap(o.At);
  Ah.swap(o.Ah);
  targets = std::move(o.targets);
  held_bytes = std::move(o.held_bytes);
  build_seconds = o.build_seconds;
  parts = o.parts;
  own_begin = o.own_begin;
  own_end = o.own_end;
  tree = std::move(o.tree);
  return *this;
}

std::size_t NormalSystem::total_held_bytes() const {
  std::size_t s = 0;
  for (auto& kv : held_bytes) s += kv.second;
  return s;
}

namespace detail {

namespace {

//! count_stencil's sums over the vertices [lo, hi): their active row blocks, and the K and C blocks of the unknowns
//! among them.
StencilCounts count_stencil_range(const EnergyOperator& op, const Unknowns& unk, int lo, int hi) {
  const Adjacency& adj = op.adjacency();
  const std::size_t b2 = static_cast<std::size_t>(op.block()) * op.block();
  StencilCounts c;
  for (int i = lo; i < hi; ++i) {
    bool active = unk.unknown_of[i] >= 0;
    for (const int* p = adj.begin(i); p != adj.end(i) && !active; ++p) active = unk.unknown_of[*p] >= 0;
    if (!active) continue;
    ++c.rows;
    const std::size_t nu = (unk.unknown_of[i] >= 0) +
                           std::count_if(adj.begin(i), adj.end(i), [&](int k) { return unk.unknown_of[k] >= 0; });
    const std::size_t m = adj.degree(i) + 1;
    c.nnz_Au += nu * b2;
    c.nnz_Ah += (m - nu) * b2;
  }
  // K's block pattern: unknown pairs within distance 2; C's: unknown-hard pairs within distance 2.
  std::vector<int> mark(static_cast<std::size_t>(adj.num_vertices()), -1);
  for (int k = lo; k < hi; ++k) {
    if (unk.unknown_of[k] < 0) continue;
    std::size_t blocks_u = 0, blocks_h = 0;
    auto visit = [&](int j) {
      if (mark[j] == k) return;
      mark[j] = k;
      if (unk.unknown_of[j] >= 0) ++blocks_u;
      else ++blocks_h;
    };
    visit(k);
    for (const int* p = adj.begin(k); p != adj.end(k); ++p) {
      visit(*p);
      for (const int* q = adj.begin(*p); q != adj.end(*p); ++q) visit(*q);
    }
    c.nnz_K_full += blocks_u * b2;
    c.nnz_C += blocks_h * b2;
  }
  return c;
}

}  // namespace

StencilCounts count_stencil(const EnergyOperator& op, const Unknowns& unk) {
  // Vertex ranges on the worker threads (serial init time on many cores otherwise); the counts are integers.
  StencilCounts c;
  std::mutex adding;
  run_ranges(op.adjacency().num_vertices(), 4096, [&](int lo, int hi) {
    const StencilCounts p = count_stencil_range(op, unk, lo, hi);
    const std::lock_guard<std::mutex> lock(adding);
    c.rows += p.rows;
    c.nnz_Au += p.nnz_Au;
    c.nnz_Ah += p.nnz_Ah;
    c.nnz_K_full += p.nnz_K_full;
    c.nnz_C += p.nnz_C;
  });
  const std::size_t nu = static_cast<std::size_t>(unk.num_unknowns()) * op.block();
  c.nnz_K_upper = (c.nnz_K_full + nu) / 2;
  return c;
}

}  // namespace detail

std::size_t predict_build_bytes(const EnergyOperator& op, const Unknowns& unk, Build build) {
  const auto c = detail::count_stencil(op, unk);
  const std::size_t b = op.block();
  const std::size_t nu = b * unk.num_unknowns(), nh = b * unk.num_hard(), rows = b * op.num_vertices();
  const std::size_t e = sizeof(double) + sizeof(int);
  const std::size_t rhs = rows * op.rhs_cols() * sizeof(double);
  switch (build) {
    case Build::Dense:
      // A_u, A_h, b, K, C and the dense Cholesky factor's own copy of K.
      return sizeof(double) * (rows * nu + rows * nh + 2 * nu * nu + nu * nh) + rhs;
    case Build::Naive:
      // triplets (row, col, value), A_u + A_h, A_u^T, full A^T A, its upper triangle, C.
      return (c.nnz_Au + c.nnz_Ah) * (2 * sizeof(int) + sizeof(double)) + (c.nnz_Au + c.nnz_Ah) * e +
             c.nnz_Au * e + c.nnz_K_full * e + c.nnz_K_upper * e + c.nnz_C * e + rhs;
    case Build::Structured:
      return c.nnz_K_upper * e + c.nnz_C * e + nu * op.rhs_cols() * sizeof(double);
  }
  return 0;
}

void check_build(const EnergyOperator& op, const Unknowns& unk, Build build, std::size_t byte_budget) {
  if (static_cast<int>(unk.unknown_of.size()) != op.num_vertices())
    throw InputError("constraint classification does not match the mesh size");
  if (unk.num_unknowns() == 0) throw InputError("nothing to solve for: every vertex is hard-constrained");
  if (byte_budget > 0) {
    const std::size_t predicted = predict_build_bytes(op, unk, build);
    if (predicted > byte_budget)
      throw BudgetError(fmt::format("{} build of the {} system needs about {:.1f} MB, over the budget of {:.1f} MB",
                                    to_string(build), to_string(op.kind()), predicted / 1e6, byte_budget / 1e6));
  }
}

void renumber_unknowns(NormalSystem& sys, const std::vector<int>& new_of_old) {
  const int b = sys.block;
  const int n = static_cast<int>(sys.K.cols());
  if (static_cast<std::size_t>(n) != static_cast<std::size_t>(b) * new_of_old.size() || sys.g0.rows() != n ||
      sys.C.rows() != n)
    throw Error(fmt::format("renumber_unknowns: a system of {} rows in blocks of {} for {} unknowns", n, b,
                            new_of_old.size()));
  auto to = [&](int i) { return b * new_of_old[static_cast<std::size_t>(i / b)] + i % b; };
  // P K P^T: entry (i, j), i <= j, of the upper triangle goes to (min, max) of (to(i), to(j)). Laid out by rows
  // first (the transpose), then by columns from rows taken in ascending order, so every column comes out sorted.
  // The old K goes once the rows hold it: two copies at a time, never three.
  const std::size_t nnz = static_cast<std::size_t>(sys.K.nonZeros());
  std::vector<int> rp(static_cast<std::size_t>(n) + 1, 0), ri(nnz);
  std::vector<double> rx(nnz);
  {
    SpMat old;
    old.swap(sys.K);
    const int* Kp = old.outerIndexPtr();
    const int* Ki = old.innerIndexPtr();
    const double* Kx = old.valuePtr();
    for (int j = 0; j < n; ++j)
      for (int k = Kp[j]; k < Kp[j + 1]; ++k) ++rp[static_cast<std::size_t>(std::min(to(Ki[k]), to(j))) + 1];
    for (int i = 0; i < n; ++i) rp[i + 1] += rp[i];
    std::vector<int> next(rp.begin(), rp.end() - 1);
    for (int j = 0; j < n; ++j)
      for (int k = Kp[j]; k < Kp[j + 1]; ++k) {
        const int a = to(Ki[k]), c = to(j);
        const int q = next[static_cast<std::size_t>(std::min(a, c))]++;
        ri[static_cast<std::size_t>(q)] = std::max(a, c);
        rx[static_cast<std::size_t>(q)] = Kx[k];
      }
  }
  SpMat K(n, n);
  K.resizeNonZeros(static_cast<Eigen::Index>(nnz));
  int* P = K.outerIndexPtr();
  std::fill(P, P + n + 1, 0);
  for (int c : ri) ++P[c + 1];
  for (int j = 0; j < n; ++j) P[j + 1] += P[j];
  std::vector<int> next(P, P + n);
  for (int r = 0; r < n; ++r)
    for (int q = rp[r]; q < rp[r + 1]; ++q) {
      const int d = next[static_cast<std::size_t>(ri[static_cast<std::size_t>(q)])]++;
      K.innerIndexPtr()[d] = r;
      K.valuePtr()[d] = rx[static_cast<std::size_t>(q)];
    }
  sys.K.swap(K);
  // C: rows move within each column, which is then sorted again (a column holds a few dozen entries).
  std::vector<std::pair<int, double>> col;
  for (int j = 0; j < sys.C.outerSize(); ++j) {
    const int lo = sys.C.outerIndexPtr()[j], hi = sys.C.outerIndexPtr()[j + 1];
    col.clear();
    for (int k = lo; k < hi; ++k) col.emplace_back(to(sys.C.innerIndexPtr()[k]), sys.C.valuePtr()[k]);
    std::sort(col.begin(), col.end());
    for (int k = lo; k < hi; ++k) {
      sys.C.innerIndexPtr()[k] = col[static_cast<std::size_t>(k - lo)].first;
      sys.C.valuePtr()[k] = col[static_cast<std::size_t>(k - lo)].second;
    }
  }
  DenseMat g(sys.g0.rows(), sys.g0.cols());
  for (Eigen::Index i = 0; i < sys.g0.rows(); ++i) g.row(to(static_cast<int>(i))) = sys.g0.row(i);
  sys.g0.swap(g);
}

namespace {

//! What every build records besides its matrices.
void label(NormalSystem& sys, const EnergyOperator& op, Build build, const Timer& t) {
  sys.build = build;
  sys.block = op.block();
  sys.rhs_cols = op.rhs_cols();
  sys.build_seconds = t.seconds();
}

}  // namespace

NormalSystem build_normal_system(const EnergyOperator& op, const Unknowns& unk, Build build,
                                 std::size_t byte_budget) {
  check_build(op, unk, build, byte_budget);
  Timer t;
  // Initialized from the builders' return values directly (see NormalSystem's move operations).
  NormalSystem sys = [&] {
    switch (build) {
      case Build::Dense: return detail::build_dense(op, unk);
      case Build::Naive: return detail::build_naive(op, unk);
      case Build::Structured: break;
    }
    return detail::build_structured(op, unk);
  }();
  label(sys, op, build, t);
  return sys;
}

std::pair<int, int> share_range(int num_unknowns, int part, int parts) {
  if (parts < 1 || part < 0 || part >= parts) throw Error(fmt::format("share_range: part {} of {}", part, parts));
  const long long nu = num_unknowns;
  return {static_cast<int>(nu * part / parts), static_cast<int>(nu * (part + 1) / parts)};
}

NormalSystem build_structured_share(const EnergyOperator& op, const Unknowns& unk, int part, int parts,
                                    std::size_t byte_budget) {
  check_build(op, unk, Build::Structured, byte_budget);
  const auto [first, last] = share_range(unk.num_unknowns(), part, parts);
  Timer t;
  NormalSystem sys = detail::build_structured(op, unk, nullptr, 0, first, last);
  sys.parts = parts;
  sys.own_begin = first;
  sys.own_end = last;
  label(sys, op, Build::Structured, t);
  return sys;
}

}  // namespace db
