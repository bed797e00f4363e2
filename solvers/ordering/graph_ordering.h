#pragma once
//! Fill-reducing ordering and symbolic analysis of a symmetric graph given by the upper triangle of its pattern,
//! shared by the structured builds' vertex ordering (systems/vertex_ordering) and the multifrontal and CHOLMOD
//! backends' orderings of block graphs.
#include <string>
#include <vector>

#include <cholmod.h>

#include "solvers/base/elimination_tree.h"

namespace db {

//! A symmetric n x n pattern as sorted CSC, of which only the upper triangle is read (the upper triangle with
//! the diagonal, or the full adjacency); not owned.
struct GraphPattern {
  int n = 0;
  const int* colptr = nullptr;
  const int* rows = nullptr;
};

//! CHOLMOD's analysis of `g` under `method` ("amd" | "metis" | "nesdis" | "natural"), postordered; simplicial
//! or supernodal (and its amalgamation) as the caller set `cc`. METIS on 20000 vertices or more is dissected
//! here: a METIS separator splits the graph into nearly equal sides, and with more than two worker threads one
//! more level of separators splits each part per doubling of the threads, and then every part larger than their
//! mean once more; the parts are ordered at once on the threads, the largest first (METIS's random draws kept per
//! thread: metis_random.h). The result is the same for one and two
//! threads, and for a given thread count on every run. With DEFORMBENCH_ORDERING_CACHE set, the ordering comes
//! from (or goes to) that cache (ordering_cache.h), per level count. The caller frees the factor.
//! `guide` (optional, g.n vertices): a sparser graph on g's vertices, such as the 1-ring graph of a 2-ring
//! pattern, on which the dissection's separators are computed, then widened and refined to separate g: cheaper
//! splits with the same fill over METIS's random draws (results/records/2026-11-27-guided-splits); the parts are
//! still ordered on g. Used only where METIS is dissected in more than one level (more than two threads).
//! \throw SolverError when CHOLMOD fails or the guide's size is not g's; Error when the cache directory cannot be
//! written.
cholmod_factor* analyze_graph(const GraphPattern& g, const std::string& method, cholmod_common& cc,
                              const GraphPattern* guide = nullptr);
//! The postordered fill-reducing order of `g` under `method` (perm[new] = old): the Perm of analyze_graph's factor
//! (the same cache, dissection and guide), without the rest of its analysis. A dissected METIS order is postordered
//! part by part on the worker threads (dissection_postorder.h) rather than by CHOLMOD's analysis of the whole graph,
//! which runs on one thread (on one thread too: the parts one after the other). `tree` (optional): where the order
//! was postordered part by part (a dissected METIS order), the graph's elimination tree and column counts in the
//! order (EliminationTree), else left empty. \throw as analyze_graph.
std::vector<int> order_graph(const GraphPattern& g, const std::string& method, const GraphPattern* guide = nullptr,
                             EliminationTree* tree = nullptr);
//! Whether analyze_graph uses a guide for an n-vertex graph under `method` at the present worker threads, so that
//! a caller builds one only then.
bool takes_guide(int n, const std::string& method);

//! CHOLMOD's analysis of `g` under the given order `perm` (perm[new] = old, g.n entries), postordered; otherwise
//! as analyze_graph (no cache: the caller computed the order). \throw SolverError when CHOLMOD fails.
cholmod_factor* analyze_graph_given(const GraphPattern& g, const std::vector<int>& perm, cholmod_common& cc);

//! METIS's fill-reducing order of `g` (perm[new] = old), not postordered; on 20000 vertices or more dissected
//! as in analyze_graph without a guide, so that every backend's METIS ordering of a matrix is the same for the same
//! graph and thread count.
//! \throw SolverError when METIS fails.
std::vector<int> metis_permutation(const GraphPattern& g);

}  // namespace db
