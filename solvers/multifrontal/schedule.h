#pragma once
//! Scheduling of the multifrontal backend: independent subtrees of the assembly tree run on separate threads
//! with a single-threaded BLAS, the few top supernodes after them with the BLAS's own threads; the solves are
//! split the same way.
#include <cstddef>
#include <functional>
#include <vector>

#include "solvers/multifrontal/symbolic.h"

namespace db::multifrontal {

//! How the assembly tree is shared among threads: subtrees per thread (processed in parallel), then the top
//! supernodes (ascending, serial).
struct Plan {
  std::vector<std::vector<int>> subtrees;  //!< per thread: the roots of its subtrees, ascending
  std::vector<int> top;
  std::vector<int> top_columns;  //!< columns of the top supernodes (rows several threads update in a solve)
  std::vector<signed char> owner;  //!< per column: thread that owns it, -1 for top columns
};

//! Splits the assembly tree into `threads` groups of independent subtrees of about equal cost (`cost[s]` of
//! each supernode, summed over a subtree) plus the top supernodes above them: the heaviest subtree is opened
//! (its root moves to the top set) until a greedy assignment of the open subtrees balances within 10%.
Plan schedule(const Symbolic& S, int threads, const std::vector<double>& cost);

//! Bytes of update matrices alive at once in a factorization by `plan`, an upper bound: each thread's subtrees in
//! order (a supernode's matrix is born while its children's still live; theirs die after it), the threads'
//! peaks summed as if they coincided, plus the matrices of the top supernodes that receive a subtree root's
//! (born during the subtree phase); or the top phase's own peak, when larger.
double update_peak(const Symbolic& S, const Plan& plan);

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

//! fn(t) for every thread t < `threads`, on threads when there are several, the BLAS single-threaded meanwhile
//! (its thread count restored afterwards, also on an exception).
void run_subtrees(std::size_t threads, const std::function<void(std::size_t)>& fn);

}  // namespace db::multifrontal
