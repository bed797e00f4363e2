#pragma once
//! Fill-reducing ordering computed on the vertex graph of a structured system, before assembly.
//! Why: the TF system is the vertex pattern expanded to 3x3 blocks, so ordering the n-vertex graph instead of
//! the 3n-unknown matrix makes the ordering several times cheaper, and numbering the unknowns in that order while
//! assembling lets the solver use the natural ordering, with no permuted copy of the matrix.
#include <string>

#include "mesh/mesh.h"
#include "systems/normal_system.h"

namespace db {

//! The vertex ordering structured builds use unless told otherwise, by block size. METIS finds less fill than
//! AMD on the 2-ring graphs of surface meshes, and markedly fewer flops (the solver study, results/solvers.md,
//! compares them). With 3x3 blocks (TF) that saves more factorization time than the ordering costs; for scalar
//! systems (LAP) the ordering time would eat the saving.
inline const char* default_vertex_ordering(int block_size) { return block_size > 1 ? "metis" : "amd"; }

//! Renumbers the unknowns of `unk` in a fill-reducing, postordered order of their interaction graph
//! (unknowns are adjacent when they share a 1-ring, i.e. the pattern of A^T A). method: "amd" | "metis" |
//! "nesdis" (solvers/ordering/graph_ordering.h's order_graph: METIS on 20000 unknowns or more is dissected and
//! runs on the worker threads, with the same result on one and two, and is postordered part by part on them) |
//! "ringnd" (solvers/ordering/ring_dissection.h: nested dissection of the 1-ring graph with widened separators,
//! then CHOLMOD's postordering analysis of the 2-ring graph). "metis" splits the graph on its 1-ring graph where it
//! dissects in two levels or more (the ordering's guide, takes_guide).
//! \throw SolverError when the ordering library fails, InputError on an unknown method.
void order_unknowns(const Adjacency& adj, Unknowns& unk, const std::string& method);
//! The same from the interaction pattern of `unk`, computed by the caller (interaction_pattern(adj, unk)), and the
//! adjacency it came from when the caller has it: without it METIS splits the 2-ring graph itself, a different
//! ordering where the guide would be taken.
void order_unknowns(const InteractionPattern& pattern, Unknowns& unk, const std::string& method,
                    const Adjacency* adj = nullptr);

//! The structured build and its vertex ordering at once, for an ordering that runs on one core (AMD, the scalar
//! LAP system's): the ordering on a second thread while this one builds in `unk`'s present numbering, both
//! from one interaction pattern; then the system is renumbered into the ordering's (renumber_unknowns) and so
//! is `unk`. Why: the serial AMD and the scalar LAP build take comparable time, and the renumbering costs less
//! than either (docs/solvers.md; the measurement: results/records/2026-11-24-readme-figures/). K is held twice
//! while it is renumbered ("K_upper_renumbering" in held_bytes).
//! `ordering_seconds`: the ordering thread's own time. Checks as build_normal_system (check_build).
NormalSystem build_structured_while_ordering(const EnergyOperator& op, Unknowns& unk, const std::string& method,
                                             std::size_t byte_budget, double& ordering_seconds);

}  // namespace db
