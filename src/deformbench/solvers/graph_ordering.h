#pragma once
//! Fill-reducing ordering and symbolic analysis of a symmetric graph given by the upper triangle of its pattern,
//! shared by the structured builds' vertex ordering (systems/vertex_ordering) and the multifrontal backend.
#include <string>

#include <cholmod.h>

namespace db {

//! Upper triangle (with the diagonal) of a symmetric n x n pattern, sorted CSC; not owned.
struct GraphPattern {
  int n = 0;
  const int* colptr = nullptr;
  const int* rows = nullptr;
};

//! CHOLMOD's analysis of `g` under `method` ("amd" | "metis" | "nesdis" | "natural"), postordered; simplicial
//! or supernodal (and its amalgamation) as the caller set `cc`. METIS on 20000 vertices or more is dissected
//! here: a METIS separator splits the graph and the two sides are ordered at once, one in a forked child
//! process (METIS draws from the C library's shared random generator, so threads would make the ordering vary
//! between runs); the result does not depend on the thread count. The caller frees the factor.
//! \throw SolverError when CHOLMOD fails.
cholmod_factor* analyze_graph(const GraphPattern& g, const std::string& method, cholmod_common& cc);

}  // namespace db
