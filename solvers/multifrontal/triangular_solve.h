#pragma once
//! The multifrontal backend's triangular solves with its factor, L y = b and L^T x = y, supernode by supernode:
//! each gathers its rows of the right-hand sides, runs the panel kernels (kernels.h) and scatters the result;
//! the subtrees of a Plan run on their threads, then the top supernodes one after another, each panel's rectangle
//! shared by a team of threads in tiles of rows (forward) or columns (backward), its triangle on one.
#include <vector>

#include <Eigen/Core>

#include "solvers/base/team.h"
#include "solvers/multifrontal/schedule.h"
#include "solvers/multifrontal/storage.h"
#include "solvers/multifrontal/symbolic.h"

namespace db::multifrontal {

//! Right-hand sides row-major: a row gathered or scattered in a solve is one cache line for all of them.
using RowMajorMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

//! The factor as the solves read it: the symbolic structure and the supernodes' FactorBlocks.
struct FactorView {
  const Symbolic& S;
  const Mapping& values;
  FactorBlock block(int s) const { return {values.get() + S.xptr[std::size_t(s)], S.nrows(s), S.ncols(s)}; }
  //! Out of core: supernode s's FactorBlock leaves the resident set (done with it for now).
  void release(int s) const {
    values.release(values.get() + S.xptr[std::size_t(s)], values.get() + S.xptr[std::size_t(s) + 1]);
  }
};

//! The mixed backend's factor rounded to float (float_factor.h), in memory: the same structure and layout.
struct FloatFactorView {
  const Symbolic& S;
  const float* values;
  FactorBlockOf<const float> block(int s) const {
    return {values + S.xptr[std::size_t(s)], S.nrows(s), S.ncols(s)};
  }
};

//! A thread's scratch in the solves: its right-hand sides gathered for one supernode, and, out of core, the one
//! panel of the factor it works on (read with Mapping::read, not through the mapping).
struct SolveScratch {
  std::vector<double> rhs, panel;
};

//! Where a subtree's thread adds its forward updates to rows it does not own: acc, not y.
struct ForeignRows {
  int thread;
  const std::vector<signed char>& owner;  //!< Plan::owner
  RowMajorMat& acc;
};

//! Flops of one triangular solve (either direction) with r right-hand sides: two per factor entry and column.
double solve_flops(const Symbolic& S, Index r);

// The solves below take either view (FactorView or FloatFactorView; instantiated for both): the same
// supernodes, threads and kernels, reading double or float entries and computing in double.

//! y_s := L_ss^{-1} y_s, then y_rows -= L_rs y_s (into foreign->acc for rows another thread owns). With a
//! `team`, its threads share the rectangles (each row's result the same as without).
template <class View>
void forward_supernode(const View& F, int s, RowMajorMat& y, SolveScratch& tmp, const ForeignRows* foreign = nullptr,
                       Team* team = nullptr);
//! y_s -= L_rs^T y_rows, then y_s := L_ss^{-T} y_s; with a `team` as forward_supernode.
template <class View>
void backward_supernode(const View& F, int s, RowMajorMat& y, SolveScratch& tmp, Team* team = nullptr);

//! y := L^{-1} y: the subtrees in parallel (contributions to top columns collected per thread in acc, one
//! matrix per thread, resized here), then the top on a team of plan.top_team threads.
template <class View>
void forward_all(const View& F, const Plan& plan, RowMajorMat& y, std::vector<RowMajorMat>& acc);
//! y := L^{-T} y: the top first (on a team of plan.top_team threads), then the subtrees in parallel.
template <class View>
void backward_all(const View& F, const Plan& plan, RowMajorMat& y);

}  // namespace db::multifrontal
