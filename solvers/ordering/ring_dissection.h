#pragma once
//! Nested dissection for the square of a graph computed on the graph itself. A structured system's pattern
//! couples the vertices within two steps of each other on the mesh (the 2-ring graph); its edges are about
//! three times the 1-ring graph's. A vertex separator of the 1-ring graph, widened by the ring of vertices on
//! one side that still reach the other side in two steps, separates the 2-ring graph: so the dissection runs
//! METIS's separators on the 1-ring graph, and only the leaves are ordered on their 2-ring graphs.
#include <vector>

namespace db {

//! A graph as full symmetric adjacency lists (each edge in both directions, no self loops, CSR), of which the
//! vertices with index[v] >= 0 are ordered (index[v]: the vertex's number among them, 0 .. m - 1). The other
//! vertices (a mesh's fixed vertices) are not ordered, but paths through them couple ordered vertices all the
//! same. Not owned.
struct RingGraph {
  int n = 0;                   //!< vertices of the graph
  const int* ptr = nullptr;    //!< n + 1 offsets into adj
  const int* adj = nullptr;    //!< neighbours of each vertex
  const int* index = nullptr;  //!< n: the vertex's number among the ordered vertices, or -1
  int m = 0;                   //!< ordered vertices
};

//! Settings of the dissection; the defaults are the project's.
struct RingDissection {
  //! Parts of fewer ordered vertices are leaves, ordered by METIS on their 2-ring graphs: below a few thousand
  //! vertices widened separators cost more fill than METIS's own (and AMD on the leaves more still).
  int leaf = 4000;
  //! Threads ordering at once (the two sides of a split, recursively); 0: worker_threads(). The result
  //! does not depend on it.
  int threads = 0;
};

//! A fill-reducing order of the ordered vertices for the pattern of vertices within two steps of each other
//! (through any vertex of the graph): perm[new] = old (numbers among the ordered vertices), not postordered.
//! Each dissection level orders its two sides first, then its widened separator; the separators come from
//! METIS (CHOLMOD's bisection) on the 1-ring graph of each part. The two sides of a split are ordered at once on
//! two threads, recursively while threads remain. Same input, same output, whatever the thread count. \throw SolverError when METIS or AMD fails.
std::vector<int> ring_dissection_order(const RingGraph& g, const RingDissection& settings = {});

}  // namespace db
