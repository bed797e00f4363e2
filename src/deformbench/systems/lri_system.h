#pragma once
//! Normal equations of LRI's two edge energies (operators/lri_rows.h), beside LAP's and TF's
//! (systems/normal_system.h). With the unknown / hard split of Unknowns:
//!
//!   K = A_u^T A_u + W   upper triangle, b#unknowns square; block pattern = the 1-ring (no 2-ring fill)
//!   C = A_u^T A_h       b#unknowns x b#hard
//!   per frame:  K x_u = A_u^T t - C x_h + W u
//!
//! returned as a NormalSystem without a constant term (g0 empty): the frame energy's targets are zero and the
//! position energy's change every frame (add_At_targets forms A_u^T t). Two builds, as for LAP and TF:
//!  - structured (lri_structured_build.cpp): K's pattern laid out from the adjacency, P^T P, P^T Q and Q^T Q
//!    accumulated edge by edge; A is never stored;
//!  - naive (lri_naive_build.cpp): A_u and A_h from triplets, then products (the reference it is checked and
//!    measured against).
//! There is no dense build.
#include <cstddef>

#include "solvers/base/types.h"
#include "mesh/mesh.h"
#include "operators/lri_rows.h"
#include "systems/normal_system.h"

namespace db {

//! \throw InputError for Build::Dense (not offered for LRI), a classification that does not match adj, nothing
//!        to solve for or a non-finite block; BudgetError when byte_budget > 0 and the predicted bytes exceed it.
NormalSystem build_edge_system(const Adjacency& adj, const Unknowns& unk, const EdgeRows& rows, Build build,
                               std::size_t byte_budget = 0);

//! Predicted peak bytes of a build (from the adjacency only).
std::size_t predict_edge_system_bytes(const Adjacency& adj, const Unknowns& unk, int block, Build build);

//! g += A_u^T t: `t` holds one b x cols block per directed edge, rows b*slot .. b*slot+b-1 (slot = index in
//! adj.nbr); g is b#unknowns x cols. Edges with both ends hard are skipped (they do not enter K).
void add_At_targets(const Adjacency& adj, const Unknowns& unk, const EdgeRows& rows, const DenseMat& t, DenseMat& g);

}  // namespace db
