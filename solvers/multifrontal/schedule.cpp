#include "solvers/multifrontal/schedule.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numeric>

#include <dlfcn.h>

#include "solvers/base/resources.h"
#include "solvers/multifrontal/storage.h"

namespace db::multifrontal {
namespace {

//! The cost of the subtree rooted at r: its supernodes are first[r] .. r (postorder).
double subtree_cost(const Symbolic& S, int r, const std::vector<double>& cost) {
  double w = 0;
  for (int s = S.first[std::size_t(r)]; s <= r; ++s) w += cost[std::size_t(s)];
  return w;
}

//! Greedy assignment of the `open` subtrees (heaviest first, each to the least loaded bin); whether the heaviest
//! bin is within 10% of the mean.
bool assign(const std::vector<int>& open, const std::vector<double>& work, std::vector<std::vector<int>>& bins) {
  std::vector<double> load(bins.size(), 0.0);
  for (auto& b : bins) b.clear();
  std::vector<int> order = open;
  std::sort(order.begin(), order.end(), [&](int a, int b) { return work[std::size_t(a)] > work[std::size_t(b)]; });
  for (int s : order) {
    const std::size_t t = std::size_t(std::min_element(load.begin(), load.end()) - load.begin());
    bins[t].push_back(s);
    load[t] += work[std::size_t(s)];
  }
  const double total = std::accumulate(load.begin(), load.end(), 0.0);
  return *std::max_element(load.begin(), load.end()) <= 1.1 * total / double(bins.size()) + 1.0;
}

//! Opens the heaviest subtree (its root to the top set, its children to `open`) until `assign` balances.
void open_until_balanced(const Symbolic& S, const std::vector<double>& work, std::vector<int>& open,
                         std::vector<char>& is_top, std::vector<std::vector<int>>& bins) {
  for (int iter = 0; iter < 4096 && !assign(open, work, bins); ++iter) {
    auto h = std::max_element(open.begin(), open.end(),
                              [&](int a, int b) { return work[std::size_t(a)] < work[std::size_t(b)]; });
    const int s = *h;
    open.erase(h);
    is_top[std::size_t(s)] = 1;
    for (int p = S.cptr[std::size_t(s)]; p < S.cptr[std::size_t(s) + 1]; ++p) open.push_back(S.child[std::size_t(p)]);
    if (open.empty()) break;
  }
  assign(open, work, bins);
}

//! P.top, P.owner and P.top_columns from the subtrees and the top set.
void mark_owners(const Symbolic& S, const std::vector<char>& is_top, Plan& P) {
  for (int s = 0; s < S.nsuper(); ++s)
    if (is_top[std::size_t(s)]) P.top.push_back(s);
  P.owner.assign(std::size_t(S.n), -1);
  for (std::size_t t = 0; t < P.subtrees.size(); ++t)
    for (int r : P.subtrees[t])
      for (int s = S.first[std::size_t(r)]; s <= r; ++s)
        for (int j = S.col0[std::size_t(s)]; j < S.col0[std::size_t(s) + 1]; ++j)
          P.owner[std::size_t(j)] = static_cast<signed char>(t);
  for (int s : P.top)
    for (int j = S.col0[std::size_t(s)]; j < S.col0[std::size_t(s) + 1]; ++j) P.top_columns.push_back(j);
}

//! `threads` (at least one per bin) over the bins in proportion to their `load`: one each, then the rest by the
//! largest remainders of the proportional shares (ties: the lower bin).
std::vector<int> proportional_threads(const std::vector<double>& load, int threads) {
  const std::size_t nb = load.size();
  const double total = std::accumulate(load.begin(), load.end(), 0.0);
  const int spare = threads - int(nb);
  std::vector<int> share(nb, 1);
  std::vector<double> rest(nb);
  int given = 0;
  for (std::size_t b = 0; b < nb; ++b) {
    const double want = total > 0 ? double(spare) * load[b] / total : double(spare) / double(nb);
    share[b] += int(std::floor(want));
    given += int(std::floor(want));
    rest[b] = want - std::floor(want);
  }
  std::vector<std::size_t> by_rest(nb);
  std::iota(by_rest.begin(), by_rest.end(), std::size_t(0));
  std::stable_sort(by_rest.begin(), by_rest.end(), [&](std::size_t a, std::size_t b) { return rest[a] > rest[b]; });
  for (std::size_t k = 0; given < spare && k < nb; ++k, ++given) ++share[by_rest[k]];
  return share;
}

}  // namespace

Plan schedule(const Symbolic& S, int threads, const std::vector<double>& cost) {
  Plan P;
  const int ns = S.nsuper();
  std::vector<double> work(std::size_t(ns), 0.0);  // of each subtree
  for (int s = 0; s < ns; ++s) {
    work[std::size_t(s)] += cost[std::size_t(s)];
    if (S.parent[std::size_t(s)] >= 0) work[std::size_t(S.parent[std::size_t(s)])] += work[std::size_t(s)];
  }
  std::vector<int> open;
  for (int s = 0; s < ns; ++s)
    if (S.parent[std::size_t(s)] < 0) open.push_back(s);
  std::vector<char> is_top(std::size_t(ns), 0);
  P.subtrees.assign(std::size_t(std::max(threads, 1)), {});
  if (threads > 1)
    open_until_balanced(S, work, open, is_top, P.subtrees);
  else
    P.subtrees[0] = open;
  for (auto& b : P.subtrees) std::sort(b.begin(), b.end());
  mark_owners(S, is_top, P);
  return P;
}

PlanCounts plan_counts(const Symbolic& S, const Plan& plan, const std::vector<double>& cost) {
  PlanCounts c;
  double groups = 0;
  for (const auto& roots : plan.subtrees) {
    double w = 0;
    for (int r : roots) w += subtree_cost(S, r, cost);
    c.group_max = std::max(c.group_max, w);
    groups += w;
  }
  c.group_mean = plan.subtrees.empty() ? 0 : groups / double(plan.subtrees.size());
  std::vector<double> path(std::size_t(S.nsuper()), 0.0);  // costliest chain ending at each top supernode
  std::vector<int> rows;
  for (int s : plan.top) {  // ascending: a top child comes before its parent
    double below = 0;
    for (int q = S.cptr[std::size_t(s)]; q < S.cptr[std::size_t(s) + 1]; ++q)
      below = std::max(below, path[std::size_t(S.child[std::size_t(q)])]);
    path[std::size_t(s)] = below + cost[std::size_t(s)];
    c.top += cost[std::size_t(s)];
    c.top_path = std::max(c.top_path, path[std::size_t(s)]);
    rows.push_back(S.nrows(s));
  }
  c.top_supernodes = int(rows.size());
  if (!rows.empty()) {
    std::sort(rows.begin(), rows.end());
    c.top_rows_median = rows[rows.size() / 2];
    c.top_rows_max = rows.back();
  }
  return c;
}

TopTree top_tree(const Symbolic& S, const Plan& plan, const std::vector<double>& cost) {
  TopTree t;
  t.children.assign(std::size_t(S.nsuper()), {});
  t.work.assign(std::size_t(S.nsuper()), 0.0);
  std::vector<char> is_top(std::size_t(S.nsuper()), 0);
  for (int s : plan.top) is_top[std::size_t(s)] = 1;
  for (int s : plan.top) {  // ascending: a child before its parent
    t.work[std::size_t(s)] += cost[std::size_t(s)];
    const int p = S.parent[std::size_t(s)];
    if (p >= 0 && is_top[std::size_t(p)]) {
      t.children[std::size_t(p)].push_back(s);
      t.work[std::size_t(p)] += t.work[std::size_t(s)];
    } else {
      t.roots.push_back(s);
    }
  }
  return t;
}

TopShares top_shares(const std::vector<int>& subtrees, const std::vector<double>& work, int threads) {
  TopShares sh;
  const std::size_t nb = std::min(subtrees.size(), std::size_t(std::max(threads, 1)));
  sh.bins.assign(nb, {});
  std::vector<double> load(nb, 0.0);
  std::vector<int> order = subtrees;
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return work[std::size_t(a)] > work[std::size_t(b)]; });
  for (int r : order) {
    const std::size_t b = std::size_t(std::min_element(load.begin(), load.end()) - load.begin());
    sh.bins[b].push_back(r);
    load[b] += work[std::size_t(r)];
  }
  for (auto& bin : sh.bins) std::sort(bin.begin(), bin.end());
  sh.threads = proportional_threads(load, std::max(threads, 1));
  for (std::size_t b = 0; b < nb; ++b) sh.threads[b] = threads_worth(load[b], Work::Dense, sh.threads[b]);
  return sh;
}

SolvePlan shortest_plan(const Symbolic& S, int most, const std::vector<double>& cost) {
  std::vector<SolvePlan> plans;
  std::vector<double> paths;
  for (int T = 1;; T = std::min(2 * T, most)) {
    Plan plan = schedule(S, T, cost);
    const PlanCounts c = plan_counts(S, plan, cost);
    paths.push_back(c.group_max + c.top);
    plans.push_back({T, std::move(plan)});
    if (T >= most) break;
  }
  const double shortest = *std::min_element(paths.begin(), paths.end());
  std::size_t k = 0;
  while (paths[k] > 1.03 * shortest) ++k;
  return std::move(plans[k]);
}

int solve_top_team(double top_work, int plan_threads, int cores) {
  const int team = std::min(threads_worth(top_work, Work::Solve, plan_threads), cores);  // at most plan_threads
  return team >= 3 ? team : 1;
}

namespace {

double update_bytes(const Symbolic& S, int s) { return double(UpdateBlock::bytes(S.nrows(s) - S.ncols(s))); }

//! Roots that may wait at their parent for an earlier sibling (Handover): every root child after the first,
//! since the threads claim subtrees in any order.
std::vector<char> may_wait(const Symbolic& S, const Plan& plan) {
  std::vector<char> root(std::size_t(S.nsuper()), 0), wait(std::size_t(S.nsuper()), 0);
  for (const auto& roots : plan.subtrees)
    for (int r : roots) root[std::size_t(r)] = 1;
  for (int p : plan.top) {
    bool earlier = false;  // a root child before this one in p's child list
    for (int q = S.cptr[std::size_t(p)]; q < S.cptr[std::size_t(p) + 1]; ++q)
      if (const int c = S.child[std::size_t(q)]; root[std::size_t(c)]) {
        wait[std::size_t(c)] = earlier;
        earlier = true;
      }
  }
  return wait;
}

//! The subtree phase's part of update_peak: the largest peaks of as many subtrees as there are groups (each
//! thread works on one at a time), plus the roots that may wait.
double subtree_peaks(const Symbolic& S, const Plan& plan) {
  const std::vector<char> wait = may_wait(S, plan);
  std::vector<double> peaks;
  double waiting = 0;
  for (const auto& roots : plan.subtrees)
    for (int root : roots) {
      double live = 0, peak = 0;
      for (int s = S.first[std::size_t(root)]; s <= root; ++s) {
        live += update_bytes(S, s);
        peak = std::max(peak, live);
        for (int q = S.cptr[std::size_t(s)]; q < S.cptr[std::size_t(s) + 1]; ++q)
          live -= update_bytes(S, S.child[std::size_t(q)]);
      }
      peaks.push_back(peak);
      if (wait[std::size_t(root)]) waiting += update_bytes(S, root);
    }
  const std::size_t k = std::min(peaks.size(), plan.subtrees.size());
  std::partial_sort(peaks.begin(), peaks.begin() + std::ptrdiff_t(k), peaks.end(), std::greater<>());
  return std::accumulate(peaks.begin(), peaks.begin() + std::ptrdiff_t(k), waiting);
}

//! The top supernodes whose update matrix a subtree root begins in the subtree phase (Handover), and their bytes.
double begun_by_roots(const Symbolic& S, const Plan& plan, std::vector<char>& begun) {
  double early = 0;
  begun.assign(std::size_t(S.nsuper()), 0);
  for (const auto& roots : plan.subtrees)
    for (int root : roots)
      if (const int p = S.parent[std::size_t(root)]; p >= 0 && !begun[std::size_t(p)]) {
        begun[std::size_t(p)] = 1;
        early += update_bytes(S, p);
      }
  return early;
}

}  // namespace

namespace {

//! top_phase_peak from the begun matrices (begun_by_roots) and their bytes.
double top_peak(const Symbolic& S, const Plan& plan, const std::vector<char>& begun, double early) {
  std::vector<char> is_top(std::size_t(S.nsuper()), 0);
  for (int s : plan.top) is_top[std::size_t(s)] = 1;
  // While a top supernode's children run (all at once, at most), their subtrees' peaks add up; then their
  // matrices live beside its own, born before theirs die. Begun matrices are counted in `early` throughout.
  std::vector<double> peak(std::size_t(S.nsuper()), 0.0);
  double roots = 0;
  for (int s : plan.top) {  // ascending: children first
    const double own = begun[std::size_t(s)] ? 0.0 : update_bytes(S, s);
    double kids_peak = 0, kids_live = 0;
    for (int q = S.cptr[std::size_t(s)]; q < S.cptr[std::size_t(s) + 1]; ++q)
      if (const int c = S.child[std::size_t(q)]; is_top[std::size_t(c)]) {
        kids_peak += peak[std::size_t(c)];
        kids_live += begun[std::size_t(c)] ? 0.0 : update_bytes(S, c);
      }
    peak[std::size_t(s)] = std::max(kids_peak, kids_live + own);
    if (const int p = S.parent[std::size_t(s)]; p < 0 || !is_top[std::size_t(p)]) roots += peak[std::size_t(s)];
  }
  return early + roots;
}

}  // namespace

double top_phase_peak(const Symbolic& S, const Plan& plan) {
  std::vector<char> begun;
  const double early = begun_by_roots(S, plan, begun);
  return top_peak(S, plan, begun, early);
}

double update_peak(const Symbolic& S, const Plan& plan) {
  std::vector<char> begun;
  const double early = begun_by_roots(S, plan, begun);
  return std::max(subtree_peaks(S, plan) + early, top_peak(S, plan, begun, early));
}

std::vector<int> claim_order(const Symbolic& S, const Plan& plan, const std::vector<double>& cost) {
  std::vector<std::pair<double, int>> roots;  // (cost of the subtree, root)
  for (const auto& group : plan.subtrees)
    for (int r : group) roots.emplace_back(subtree_cost(S, r, cost), r);
  std::sort(roots.begin(), roots.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first > b.first : a.second < b.second;
  });
  std::vector<int> order;
  for (const auto& [w, r] : roots) order.push_back(r);
  return order;
}

BlasThreads::BlasThreads() {
  void* self = ::dlopen(nullptr, RTLD_LAZY);
  set_ = reinterpret_cast<void (*)(int)>(::dlsym(self, "openblas_set_num_threads"));
  get_ = reinterpret_cast<int (*)()>(::dlsym(self, "openblas_get_num_threads"));
}

const BlasThreads& blas_threads() {
  static const BlasThreads b;
  return b;
}

Handover::Handover(const Symbolic& S, const Plan& plan)
    : S_(S), root_(std::size_t(S.nsuper()), 0), done_(std::size_t(S.nsuper()), 0), next_(std::size_t(S.nsuper()), 0) {
  for (const auto& roots : plan.subtrees)
    for (int r : roots) root_[std::size_t(r)] = 1;
}

void Handover::finished(int root, const std::function<void(int, int)>& assemble) {
  const int p = S_.parent[std::size_t(root)];
  if (p < 0) return;
  const std::lock_guard<std::mutex> lock(mutex_);
  done_[std::size_t(root)] = 1;
  const int begin = S_.cptr[std::size_t(p)], end = S_.cptr[std::size_t(p) + 1];
  for (int& k = next_[std::size_t(p)]; begin + k < end; ++k) {
    const int c = S_.child[std::size_t(begin + k)];
    if (!root_[std::size_t(c)]) continue;  // a top child: the top phase assembles it
    if (!done_[std::size_t(c)]) break;
    assemble(c, p);
  }
}

int threads_worth(double flops, Work kind, int most) {
  // Rough rates of one core: dense factorization work (BLAS-3) and triangular solves, which stream the factor
  // from memory. The tests lower the bound (DEFORMBENCH_PARALLEL_MIN_SECONDS=0) to run small systems' plans on
  // threads.
  static const double min_seconds = [] {
    const char* e = std::getenv("DEFORMBENCH_PARALLEL_MIN_SECONDS");
    return e && *e ? std::strtod(e, nullptr) : 2e-3;
  }();
  const double flops_per_second = kind == Work::Dense ? 2e10 : 2.5e9;
  const double seconds = flops / flops_per_second;
  if (most <= 1) return 1;
  if (!(min_seconds > 0)) return most;
  return int(std::clamp(std::floor(seconds / min_seconds) + 1, 1.0, double(most)));
}

bool worth_threads(double flops, Work kind) { return threads_worth(flops, kind, 2) > 1; }

BlasOnOneThread::BlasOnOneThread() : saved_(blas_threads().get()) { blas_threads().set(1); }
BlasOnOneThread::~BlasOnOneThread() { blas_threads().set(saved_); }

void run_subtrees(std::size_t groups, bool parallel, const std::function<void(std::size_t)>& fn) {
  if (groups <= 1) {
    if (groups == 1) fn(0);
    return;
  }
  const BlasOnOneThread one_thread;
  if (parallel)
    run_tasks(int(groups), [&](int t) { fn(std::size_t(t)); });
  else
    for (std::size_t t = 0; t < groups; ++t) fn(t);
}

}  // namespace db::multifrontal
