#pragma once
//! Scheduling of the multifrontal backend: independent subtrees of the assembly tree run on separate threads
//! with a single-threaded BLAS (the factorization's threads claim them one at a time, the solves' take a group
//! each), the few top supernodes after them, each shared by a team of threads in tiles (front.h): the solves'
//! one at a time, the factorization's independent top subtrees at once on teams of their own (top_phase.h).
//!
//! Determinism: the plan depends only on the tree and the thread count, and every floating-point sum is taken in
//! an order the plan fixes (the subtree roots' hand-over to their parents in child order, the solves' per-thread
//! accumulators added in thread order). Running a plan's groups one after another on one thread gives the same
//! bytes as running them on threads: that is how a job too small for threads runs (worth_threads).
#include <cstddef>
#include <functional>
#include <mutex>
#include <vector>

#include "solvers/multifrontal/symbolic.h"

namespace db::multifrontal {

//! How the assembly tree is shared among threads: subtrees per thread (processed in parallel), then the top
//! supernodes (ascending: each after its children).
struct Plan {
  std::vector<std::vector<int>> subtrees;  //!< per thread: the roots of its subtrees, ascending
  std::vector<int> top;
  std::vector<int> top_columns;  //!< columns of the top supernodes (rows several threads update in a solve)
  std::vector<signed char> owner;  //!< per column: thread that owns it, -1 for top columns
  int top_team = 1;  //!< solves: the threads of a team that shares the top supernodes (1: they run serially)
};

//! Splits the assembly tree into `threads` groups of independent subtrees of about equal cost (`cost[s]` of
//! each supernode, summed over a subtree) plus the top supernodes above them: the heaviest subtree is opened
//! (its root moves to the top set) until a greedy assignment of the open subtrees balances within 10%.
Plan schedule(const Symbolic& S, int threads, const std::vector<double>& cost);

//! A solve's plan: of the thread counts up to `most` (the powers of two below it, and `most`), the fewest whose
//! plan's critical path in `cost` (its largest group plus every top supernode, which the solves take serially) is
//! within 3% of the shortest, with its plan. Why: a plan for more threads opens more subtrees to balance more
//! groups, moving entries into the serial top, so that past some count the path, and the solve with it, grows
//! (counted by exp_tree_parallelism's solve columns; measured on 16 cores in results/records/2026-11-26-threads).
//! Depends only on the tree, `most` and the costs: a solve's bytes stay fixed for a given thread count.
struct SolvePlan {
  int threads = 1;
  Plan plan;
};
SolvePlan shortest_plan(const Symbolic& S, int most, const std::vector<double>& cost);

//! The solves' top team (Plan::top_team) for a top of `top_work` flops (both directions), under a plan made for
//! `plan_threads` threads: as many threads as the top's work is worth (threads_worth), no more than `cores` (each
//! step waits for its tiles) nor `plan_threads`, and 1 (the top serial) below three. Why no more than the plan's:
//! shortest_plan takes a plan for fewer threads than allowed where more would not shorten the path, and a larger
//! team then only adds helpers each top step waits for (the 416k TF solve takes the 8-thread plan at 16 threads:
//! results/records/2026-11-28-head-16-cores; its measured effect: 2026-11-28-serial-passes). Not by two: with two
//! threads the top is a small part of the solve, and a step that waits for a helper another process has
//! descheduled cost more than the half of it a second thread saves (on 2 cores beside a busy loop,
//! results/records/2026-11-27-top-team).
int solve_top_team(double top_work, int plan_threads, int cores);

//! What a plan leaves to each phase, in the costs it was made with (flops for the factorization's plan): the
//! largest and the mean group of the subtree phase, and the top phase: its supernodes, each shared by a team's
//! threads in tiles, and its costliest chain, which the factorization's independent top subtrees running at once
//! (top_phase.h) cannot shorten. Why: the top phase's share grows with the thread count (more subtrees opened to
//! balance more groups), and whether it or the subtrees limit a factorization on many cores can be counted on
//! any machine.
struct PlanCounts {
  double group_max = 0, group_mean = 0;  //!< cost of the subtree phase's groups
  double top = 0;                        //!< cost of the top supernodes
  double top_path = 0;                   //!< the costliest chain of top supernodes (child to parent)
  int top_supernodes = 0;
  int top_rows_median = 0, top_rows_max = 0;  //!< rows of the top supernodes' fronts
};
PlanCounts plan_counts(const Symbolic& S, const Plan& plan, const std::vector<double>& cost);

//! The top supernodes as a tree: each one's top children (ascending) and the cost of its top subtree (itself and
//! the top supernodes below it), and the top supernodes without a top parent (ascending). Independent top
//! subtrees (siblings, or roots) can be factored at once (top_phase.h).
struct TopTree {
  std::vector<std::vector<int>> children;  //!< per supernode; empty unless top
  std::vector<double> work;                //!< per supernode: its top subtree's cost; 0 unless top
  std::vector<int> roots;
};
TopTree top_tree(const Symbolic& S, const Plan& plan, const std::vector<double>& cost);

//! How independent top subtrees (`subtrees`, their flops in `work`) share `threads`: at most `threads` bins of
//! them (costliest first, each to the lightest bin, ties to the lower bin), each bin run one subtree after another
//! by its own threads, their number in proportion to the bin's flops (largest remainders; at least one each) and
//! no more than those are worth (threads_worth), in all at most `threads`. Depends only on the flops and
//! `threads`, so the teams do too (the bytes do not depend on them anyway).
struct TopShares {
  std::vector<std::vector<int>> bins;
  std::vector<int> threads;
};
TopShares top_shares(const std::vector<int>& subtrees, const std::vector<double>& work, int threads);

//! The factorization's subtree phase: the roots of all the plan's subtrees, costliest first (ties: ascending),
//! the order in which its threads claim them one at a time. Why not each thread its group: on 16 cores the
//! groups' times spread more than their flops (a group of many small subtrees costs more a flop), so the phase
//! waited for the slowest group long after the first was done (results/records/2026-11-27-subtree-phase);
//! claimed, a thread done early takes the next subtree. The bytes do not change: a subtree's work and its root's
//! hand-over (child order, Handover) do not depend on the thread.
std::vector<int> claim_order(const Symbolic& S, const Plan& plan, const std::vector<double>& cost);

//! Bytes of update matrices alive at once in a factorization by `plan`, its subtrees claimed in any order by as
//! many threads as the plan has groups, an upper bound: the largest peaks of that many subtrees (in each, a
//! supernode's matrix is born while its children's still live; theirs die after it) summed as if they coincided,
//! plus every root that may wait for an earlier sibling's hand-over (Handover), plus the matrices of the top
//! supernodes that receive a subtree root's (born during the subtree phase); or the top phase's own peak, when
//! larger, counted as if all independent top subtrees ran at once: a bound for any way top_phase.h runs them.
double update_peak(const Symbolic& S, const Plan& plan);
//! update_peak's top phase part: the matrices begun in the subtree phase, plus the top's own, independent top
//! subtrees' peaks added as if they coincided.
double top_phase_peak(const Symbolic& S, const Plan& plan);

//! The subtree phase's hand-over of each subtree root's update matrix to its (top) parent, early rather than when
//! the top phase reaches the parent (else every root's update would be resident at once), in a fixed order: a
//! parent takes its root children in the order of its child list, whichever thread finishes first, so that the
//! sums into its front do not depend on thread timing. A root finished before an earlier sibling keeps its
//! update matrix until that sibling is handed over.
class Handover {
 public:
  Handover(const Symbolic& S, const Plan& plan);
  //! Subtree root `root` is factored: under one lock, assemble(child, parent) for each root that is now next in
  //! line at its parent (this one, and later siblings that finished before it).
  void finished(int root, const std::function<void(int child, int parent)>& assemble);

 private:
  const Symbolic& S_;
  std::mutex mutex_;
  std::vector<char> root_, done_;  //!< per supernode: a subtree root; a root finished
  std::vector<int> next_;          //!< per supernode: position in its child list of the next child to take
};

//! Whether a job of `flops` floating-point operations is worth running on threads: below about two milliseconds
//! of one core's work, a worker's start and, on a machine where another process holds a core, its wait for a
//! scheduler slice cost more than the share it takes over. A job that is not runs its plan's groups serially.
//! Dense work (the factorization's fronts) runs several times more flops a second than the solves, which stream
//! the factor from memory.
enum class Work { Dense, Solve };
bool worth_threads(double flops, Work kind);
//! How many threads a job of `flops` is worth, from 1 to `most`: one more for each share of one core's work
//! that worth_threads asks before it starts a second. Why: a thread with less work costs more in its start and
//! its share of the serial top (a plan for more threads opens more subtrees) than it takes over.
int threads_worth(double flops, Work kind, int most);

//! OpenBLAS runs its own thread pool; while our threads each work on a subtree it must run single-threaded
//! (two pools on the same cores oversubscribe them). Looked up at run time: other BLAS builds simply lack the
//! symbols, and then get() is 1 and set() does nothing.
class BlasThreads {
 public:
  BlasThreads();
  int get() const { return get_ ? get_() : 1; }
  void set(int n) const {
    if (set_) set_(n);
  }

 private:
  void (*set_)(int) = nullptr;
  int (*get_)() = nullptr;
};
const BlasThreads& blas_threads();

//! The BLAS single-threaded for one scope, its thread count restored afterwards (also on an exception).
class BlasOnOneThread {
 public:
  BlasOnOneThread();
  ~BlasOnOneThread();
  BlasOnOneThread(const BlasOnOneThread&) = delete;
  BlasOnOneThread& operator=(const BlasOnOneThread&) = delete;

 private:
  int saved_;
};

//! fn(t) for every group t < `groups` of a plan, the BLAS single-threaded meanwhile (its thread count restored
//! afterwards, also on an exception): as tasks on up to `groups` threads (run_tasks) when `parallel`, else one after
//! another on the calling thread (the same results, bit for bit).
void run_subtrees(std::size_t groups, bool parallel, const std::function<void(std::size_t)>& fn);

}  // namespace db::multifrontal
