#pragma once
//! Normal equations of a constrained Laplacian-type energy, in the precompute / per-frame split of
//! interactive editing. Unknowns are the vertices not hard-constrained ("free" and "soft"):
//!
//!   min ||A_u x_u + A_h x_h - b||^2 + sum_{soft s} w^2 ||x_s - u_s||^2
//!   =>  (A_u^T A_u + W) x_u = A_u^T b - (A_u^T A_h) x_h + W u        (W = w^2 on soft vertices)
//!         \_____ K _____/     \_ g0 _/   \___ C ___/
//!
//! K (upper triangle), C and g0 are built once per edit; per frame only x_h and u change.
//! Three builds give the same K (the thesis Table 2-1 comparison):
//!  - structured: K from the 2-ring stencil of the adjacency, A never stored;
//!  - naive sparse: A assembled from triplets, A^T formed explicitly, A^T A by a sparse product;
//!  - dense: A and A^T A as dense matrices.
//! LRI's edge energies give systems of the same form (systems/lri_system.h); systems/min_quad_with_fixed.h
//! factors any of them and solves it per frame.
#include <cstddef>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/enum_text.h"
#include "solvers/base/elimination_tree.h"
#include "solvers/base/types.h"
#include "mesh/mesh.h"
#include "operators/energy_operator.h"

namespace db {

enum class Build { Dense, Naive, Structured };
const EnumText<Build>& enum_text(Build);  //!< "dense" | "naive" | "structured" (core/enum_text.h)

//! How each vertex enters the system.
enum class Constraint : unsigned char { Free, Hard, Soft };

//! Vertex -> unknown numbering. Unknown vertex u occupies scalar rows block*u .. block*u+block-1.
struct Unknowns {
  std::vector<int> unknown_of;  //!< per vertex: unknown index, or -1 when hard-constrained
  std::vector<int> hard_of;     //!< per vertex: index among hard vertices, or -1
  std::vector<int> unknown_vertices, hard_vertices;
  std::vector<int> soft_vertices;  //!< subset of unknowns with a soft (weighted) target
  double soft_weight = 1.0;
  //! The elimination tree and column counts of the unknowns' 2-ring interaction graph in their numbering, where
  //! the vertex ordering that numbered them found it (a dissected METIS ordering: 20000 unknowns or more); else null.
  std::shared_ptr<const EliminationTree> tree;

  int num_unknowns() const { return static_cast<int>(unknown_vertices.size()); }
  int num_hard() const { return static_cast<int>(hard_vertices.size()); }
};
Unknowns make_unknowns(const std::vector<Constraint>& kind, double soft_weight);

struct NormalSystem {
  // Moves swap the sparse matrices: Eigen 3.4's SparseMatrix has no move operations, so the implicit ones
  // copied K, the build's largest matrix, wherever a built system was assigned.
  NormalSystem() = default;
  NormalSystem(const NormalSystem&) = default;
  NormalSystem& operator=(const NormalSystem&) = default;
  NormalSystem(NormalSystem&& o) noexcept;
  NormalSystem& operator=(NormalSystem&& o) noexcept;

  Build build = Build::Structured;
  int block = 1;     //!< 1 (LAP) or 3 (TF)
  int rhs_cols = 3;  //!< 3 (LAP: x, y, z) or 1 (TF)
  SpMat K;           //!< upper triangle of A_u^T A_u + W, (block*#unknowns)^2; sparse builds
  SpMat C;           //!< A_u^T A_h, block*#unknowns x block*#hard; sparse builds
  DenseMat K_dense;  //!< dense build: full A_u^T A_u + W
  DenseMat C_dense;  //!< dense build
  //! A_u^T b, block*#unknowns x rhs_cols; empty for an energy without a constant term (LRI's: zero targets, or
  //! targets that change every frame)
  DenseMat g0;
  //! LAP / TF naive build only: what the thesis' first version kept for the frames (section 2.4.1: the
  //! factorization and the back-substitution held A^T beside the factor), its right-hand side formed each frame as
  //! A_u^T (b - A_h x_h) instead of from g0 and C. Empty for the other builds (LRI's naive build included).
  SpMat At;          //!< A_u^T, block*#unknowns x block*#vertices
  SpMat Ah;          //!< A_h, block*#vertices x block*#hard
  DenseMat targets;  //!< b, the operator's targets, block*#vertices x rhs_cols

  //! Bytes of every matrix the build held at its peak (name -> bytes), e.g. {"A", ...}, {"At", ...}.
  std::vector<std::pair<std::string, std::size_t>> held_bytes;
  double build_seconds = 0;
  //! One of `parts` > 1 rank shares (build_structured_share): K holds the block columns, C and g0 the rows of the
  //! unknowns [own_begin, own_end) only, and the parts' K, C and g0 sum to the whole system's. 1: the whole system.
  int parts = 1, own_begin = 0, own_end = 0;
  //! The structured LAP / TF builds of the whole system: Unknowns::tree, the elimination tree of K's block graph
  //! (which is the 2-ring interaction graph), when the vertex ordering found it; else null.
  std::shared_ptr<const EliminationTree> tree;

  //! Unknowns (scalar): g0's rows, which outlive K when a solver consumed it, or K's order when g0 is empty.
  std::size_t n() const { return static_cast<std::size_t>(g0.rows() > 0 ? g0.rows() : K.rows()); }
  //! Sum of held_bytes.
  std::size_t total_held_bytes() const;
};

//! Vertex-level CSC pattern of the upper triangle of a normal matrix, in unknown numbering: unknowns j <= k
//! interact when they are at most `rings` edges apart (2 for A^T A of 1-ring operators such as LAP and TF,
//! 1 for edge-based ones such as LRI's). Rows ascend per column; the diagonal comes last. With a column range
//! [first, last) (last -1: every column) the columns outside it are left empty (a rank share's pattern).
struct InteractionPattern {
  std::vector<int> colptr, rows;
  //! Index into `rows` of (row, col); the entry must exist.
  int find(int col, int row) const;
  //! Position of `row` within column `col`.
  int slot(int col, int row) const { return find(col, row) - colptr[col]; }
};
InteractionPattern interaction_pattern(const Adjacency& adj, const Unknowns& unk, int rings = 2, int first = 0,
                                       int last = -1);

//! Scalar upper-triangular CSC (values zero) of the pattern expanded to b x b blocks: entry (b*j + c1, b*k + c2)
//! sits at outer[b*k + c2] + b * slot(k, j) + c1; diagonal blocks keep only c1 <= c2.
SpMat expand_upper(const InteractionPattern& p, int b);

//! Builds the normal system. \throw BudgetError when `byte_budget` > 0 and the predicted bytes of the
//! build exceed it (checked before allocating).
NormalSystem build_normal_system(const EnergyOperator& op, const Unknowns& unk, Build build,
                                 std::size_t byte_budget = 0);

//! Part `part` of the structured system split over `parts` processes (MPI ranks, distributed assembled input):
//! the unknowns [nu part / parts, nu (part + 1) / parts) (share_range), their block columns of K, their rows of
//! C and g0 (the soft weights of those among them); the parts' K, C and g0 sum to build_normal_system's
//! (Build::Structured). No part forms more of K than its columns. Checks as build_normal_system (the budget
//! against the whole system's prediction).
NormalSystem build_structured_share(const EnergyOperator& op, const Unknowns& unk, int part, int parts,
                                    std::size_t byte_budget = 0);
//! The unknowns part `part` of `parts` owns: [nu part / parts, nu (part + 1) / parts).
std::pair<int, int> share_range(int num_unknowns, int part, int parts);

//! \throw InputError when `unk` does not fit the operator or leaves nothing to solve for, BudgetError when
//! `byte_budget` > 0 and the build's predicted bytes exceed it (build_normal_system's checks).
void check_build(const EnergyOperator& op, const Unknowns& unk, Build build, std::size_t byte_budget);

//! Renumbers the unknowns of a sparse build: unknown u becomes new_of_old[u]. K stays the upper triangle with
//! ascending rows in every column; the rows of C and g0 move along.
void renumber_unknowns(NormalSystem& sys, const std::vector<int>& new_of_old);

//! Predicted peak bytes of the matrices a build holds, from the adjacency alone (no allocation).
std::size_t predict_build_bytes(const EnergyOperator& op, const Unknowns& unk, Build build);

//! Bytes of a compressed sparse matrix (values, inner indices, outer pointers).
std::size_t sparse_bytes(const SpMat& m);

}  // namespace db
