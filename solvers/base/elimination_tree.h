#pragma once
//! The elimination tree of a symmetric graph in a given order and the column counts of its Cholesky factor, both
//! by position in that order: what a dissected METIS ordering finds part by part on the worker threads on its way
//! to its postorder (solvers/ordering/dissection_postorder.h). Why a type of its own: a caller hands them with the
//! ordered matrix (SolverOptions::elimination_tree), so that the backend's analysis does not find them again on
//! one thread.
#include <cstddef>
#include <vector>

namespace db {

struct EliminationTree {
  std::vector<int> parent;  //!< parent of each position in the tree; -1 at a root
  std::vector<int> count;   //!< entries of each column of the graph's Cholesky factor, its diagonal included
  //! Entries of the graph's upper triangle with the diagonal (edges + vertices): a check that a matrix's graph is
  //! the one the tree was found for.
  std::size_t upper_entries = 0;
};

}  // namespace db
