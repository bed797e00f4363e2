#pragma once
//! The factorization's top phase: the top supernodes (those above the subtree phase's subtrees), each after its
//! top children, each front shared by a team of threads in tiles (front.h). Where a top supernode has several top
//! children, or the top several roots, their top subtrees are independent: they run at once, each bin of them on
//! a team of its own sized by its flops (top_shares, schedule.h), and the supernode above them then runs on its
//! own team again.
//!
//! Why: on many threads the top holds a large share of a TF factorization's flops in dozens of fronts, and its
//! costliest chain only part of those (counted by exp_tree_parallelism; results/records/2026-11-26-tree-parallelism).
//! One front after another on one team of all the threads, each front's serial steps (a panel's dpotrf, the matrix
//! entries) left the others waiting and its tiles were shared too many ways: the top phase ran longer on 16 threads
//! than on 8 (results/records/2026-11-28-given-tree). On 2 cores, independent top subtrees on a thread each beat
//! one team of two on the 104k TF top of a 16-thread plan, and were even on the 416k one, whose fronts are large
//! (results/records/2026-11-28-top-branches). On 16 cores the 104k TF top is shorter than on one team and the
//! 416k one longer: bins even in flops are uneven in time, and a team that finishes its bin early does not lend
//! its threads to the others (results/records/2026-11-28-head-16-cores).
//!
//! The bytes do not depend on the teams or on which runs first: a front's tiles depend only on the front (Tiles,
//! team.h), and a supernode starts only once its top children are done, assembling them in child order.
#include <functional>
#include <memory>

#include "solvers/base/team.h"
#include "solvers/base/types.h"
#include "solvers/multifrontal/front.h"
#include "solvers/multifrontal/matrix_chunk.h"
#include "solvers/multifrontal/schedule.h"
#include "solvers/multifrontal/storage.h"

namespace db::multifrontal {

//! One thread's scratch for its run of top supernodes: the front's workspace, the matrix entries, the release of
//! the matrix's dead columns.
struct TopScratch {
  Workspace ws;
  MatrixChunk chunk;
  ColumnRelease release;
  TopScratch(int n, const SpMat& A, bool may_release) : ws(n), release(A, may_release) {}
};

//! Factors top supernode s on `team` with `scratch`; false (a pivot failed) stops the phase.
using TopFront = std::function<bool(int s, Team& team, TopScratch& scratch)>;

//! Every supernode of `tree` by `front`, each after its top children, on `threads` threads in all; `scratch`
//! makes one thread's scratch. False when a front returned false (the fronts not yet started then do not run).
bool run_top_phase(const TopTree& tree, int threads, const std::function<std::unique_ptr<TopScratch>()>& scratch,
                   const TopFront& front);

}  // namespace db::multifrontal
