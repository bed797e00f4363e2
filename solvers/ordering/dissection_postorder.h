#pragma once
//! The postorder of a nested-dissection order, found part by part on threads: the permutation that CHOLMOD's
//! postordered analysis makes of the order (its elimination tree postordered, each node's children by increasing
//! column count), without CHOLMOD's serial pass over the whole graph.
//! Why by hand around CHOLMOD: that pass (the permuted transpose, the elimination tree, the column counts) runs on
//! one thread whatever the thread count. Here each part's tree and counts come from CHOLMOD's analysis of the part
//! with the separator vertices it touches, the parts on threads at once; only the separators' tree and counts are
//! found on one thread, from CHOLMOD's analysis of a small graph: the separator vertices, their edges, and for each
//! connected piece of a part, edges from its first separator neighbour to the others (a piece couples all its
//! separator neighbours once it is eliminated, and a star from the first of them fills in to that clique). The tree
//! and the counts are the whole graph's, exactly; the postorder is cholmod_postorder's, as in CHOLMOD's analysis.
#include <vector>

#include "solvers/base/elimination_tree.h"
#include "solvers/ordering/graph_ordering.h"

namespace db {

//! Positions [lo, hi) of an order.
struct PositionRange {
  int lo = 0, hi = 0;
};

//! `order` (order[new] = old, adjacency.n entries) postordered: the Perm of CHOLMOD's postordered analysis of the
//! graph under `order`. `adjacency`: the graph's adjacency lists (each edge both ways, no diagonal). `parts`:
//! disjoint ranges of positions such that every edge from a part's vertex leads into the part or to a separator
//! vertex (in no part) at a later position: a nested dissection's parts, each separator after the parts it
//! separates. The parts are analyzed on up to `threads` threads; the result does not depend on `threads`.
//! `tree` (optional): the graph's elimination tree and column counts in the postordered order, as CHOLMOD's analysis
//! of the graph in that order finds them.
//! \throw SolverError when CHOLMOD fails or `parts` are not such ranges.
std::vector<int> postorder_dissection(const GraphPattern& adjacency, const std::vector<int>& order,
                                      const std::vector<PositionRange>& parts, int threads,
                                      EliminationTree* tree = nullptr);

}  // namespace db
