#pragma once
//! Factories of the individual backends; registry.cpp maps names to them. Internal to solvers/.
#include <memory>

#include "solvers/linear_solver.h"

namespace db::backends {

//! CHOLMOD, supernodal LL^T (`supernodal` true) or simplicial LDL^T.
std::unique_ptr<LinearSolver> make_cholmod(bool supernodal, const SolverOptions& options);

}  // namespace db::backends
