#pragma once
//! Full adjacency lists of a graph given by its upper triangle (each edge both ways, no self loops, every list
//! ascending): what METIS reads and what the dissection's postorder walks. Why a threaded transpose of its own: on
//! many cores the serial one was a visible step of the analysis before the dissection's first split
//! (results/records/2026-11-28-given-tree). Ranges of columns, about equal in entries, count and then fill their
//! own entries at offsets fixed by prefix sums over the ranges, so the lists do not depend on the range count.
#include <vector>

#include "solvers/ordering/graph_ordering.h"

namespace db {

struct AdjacencyLists {
  std::vector<int> xadj{0};  //!< n + 1 offsets into adjncy
  std::vector<int> adjncy;
};

//! The adjacency lists of `upper` (only entries above the diagonal are read), built by `ranges` ranges of columns
//! on threads (at least 1; at most one per column).
AdjacencyLists adjacency_lists(const GraphPattern& upper, int ranges);

//! Ranges worth starting for adjacency_lists of a pattern of `entries` entries: the worker threads, up to one per
//! few hundred thousand entries and at most eight (each range holds an n-entry count array).
int adjacency_ranges(long entries);

}  // namespace db
