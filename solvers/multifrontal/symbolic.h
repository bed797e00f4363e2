#pragma once
//! Symbolic analysis of the multifrontal backend: CHOLMOD's supernodal analysis (ordering, elimination tree,
//! postorder, relaxed supernodes) run on the compressed block (vertex) graph, ~b^2 times smaller than the
//! matrix, and expanded to its b x b blocks: with dense blocks the factor of the expanded matrix is exactly the
//! expanded factor of the block graph. The compression to blocks and the expansion run on the worker threads, in
//! ranges fixed by the thread count and concatenated in order: the same Symbolic for any thread count.
#include <cstddef>
#include <string>
#include <vector>

#include "solvers/base/elimination_tree.h"
#include "solvers/base/types.h"

namespace db::multifrontal {

//! Symbolic factorization at the scalar level. Supernodes are numbered in a postorder of the assembly tree,
//! so the subtree of s is the contiguous range [first[s], s].
struct Symbolic {
  int n = 0;
  std::vector<int> perm;  //!< perm[k] = original index of unknown k; empty when the identity
  std::vector<int> col0;  //!< nsuper + 1: first column of each supernode
  std::vector<int> rptr;  //!< nsuper + 1: offsets into rows
  std::vector<int> rows;  //!< row indices of each supernode, its own columns first, ascending
  std::vector<std::size_t> xptr;  //!< nsuper + 1: offsets of the supernodes' FactorBlocks
  std::vector<int> parent, first;
  std::vector<int> cptr, child;  //!< children lists
  double flops = 0;
  std::size_t nnz = 0;

  int nsuper() const { return int(col0.size()) - 1; }
  int ncols(int s) const { return col0[std::size_t(s) + 1] - col0[std::size_t(s)]; }
  int nrows(int s) const { return rptr[std::size_t(s) + 1] - rptr[std::size_t(s)]; }
};

//! Flops of the dense work of supernode s (sum over its columns of (column count)^2, as CHOLMOD counts).
double supernode_flops(const Symbolic& S, int s);

//! The "default" ordering for blocks of b unknowns: METIS for block systems, AMD for scalar ones, as the
//! structured builds' vertex orderings (systems/vertex_ordering.h) choose: on the 2-ring graphs of TF systems
//! METIS's factor takes markedly fewer flops than AMD's, for little ordering time. CHOLMOD's own rule, applied to the smaller block
//! graph, would keep AMD.
const char* default_ordering(int b);

//! CHOLMOD's supernodal symbolic analysis of the block graph of `upper` (the upper triangle, compressed; blocks of
//! b unknowns) under ordering `method` ("default" or one CHOLMOD takes), postordered, with relaxed supernodes,
//! expanded to b x b blocks. `tree` (optional, taken only with method "natural"): the block graph's elimination tree
//! and column counts, postordered; CHOLMOD's supernodal analysis then starts from them rather than from its own pass
//! over the graph (its transposes, tree, postorder and counts, on one thread): the same Symbolic where they are the
//! graph's. \throw SolverError when CHOLMOD fails, its tree is not as expected, or `tree` does not fit the graph
//! (check_tree).
Symbolic analyze_blocks(const SpMat& upper, int b, const std::string& method, const EliminationTree* tree = nullptr);

//! Checks that `tree` may be the elimination tree and column counts of the graph `g` (its upper triangle with the
//! diagonal, rows ascending) in g's order, postordered: its size and g's upper entries; every parent later than its
//! child and every subtree the contiguous positions before its root; every edge (i, j), i < j, joining j to a
//! descendant; a root's count 1, any other count at least 2, at most the positions from it on, and at most one more
//! than its parent's. Necessary, not sufficient: a wrong count that keeps these is not seen. Why not recompute: that
//! is the serial pass the tree is handed on to save. \throw SolverError naming the first misfit.
void check_tree(const EliminationTree& tree, int n, const int* colptr, const int* rows);

}  // namespace db::multifrontal
