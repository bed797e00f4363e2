#pragma once
// The mesh-level side of solvers/tests/exact_reference.h, for tests that check a lap or tf deformation's accuracy:
// the exact deformation (multifrontal_refined refined to exact::kExactTolerance), the condition of the system the
// deformer solves, and distances in the deformer's normalized coordinates, where that system's unknowns live.
#include "methods/deformer.h"
#include "methods/lri.h"
#include "methods/normalization.h"
#include "operators/energy_operator.h"
#include "solvers/tests/exact_reference.h"
#include "systems/normal_system.h"

namespace db {

//! `o` with the exact backend: multifrontal_refined at exact::kExactTolerance, on the structured build.
inline DeformOptions exact_options(DeformOptions o) {
  o.solver = "multifrontal_refined";
  o.build = Build::Structured;
  o.solver_options.tolerance = exact::kExactTolerance;
  return o;
}

//! cond_2 of the normal matrix K a lap or tf deformer with options `o` factors (normalized coordinates, as
//! LaplacianDeformer builds it; TfScale::Normalized's second system is not included).
inline double system_condition(const Mesh& m, const Edit& e, const DeformOptions& o) {
  const Points Vn = (o.normalize ? Normalization::fit(m.V) : Normalization::identity()).apply(m.V);
  EnergyOptions eo;
  eo.weights = o.weights;
  eo.tf_translation = o.tf_translation;
  const Adjacency adj = vertex_adjacency(m);  // the operator keeps a reference
  const EnergyOperator op(Vn, m.F, adj, o.method == Method::Tf ? EnergyKind::Tf : EnergyKind::Lap, eo);
  const Unknowns unk = make_unknowns(classify(e, o.constraints), o.soft_weight);
  return exact::condition_number(build_normal_system(op, unk, Build::Structured).K);
}

//! The relative error (normalized_rel) a deformation with options `o` may have from the exact one. lap, tf: a
//! backward-stable solve's, exact::solve_bound(cond K). lri: its frame solve's relative error e_F, and the position
//! solve's, which takes the frames' error into its right-hand side and multiplies it by cond(K_P):
//! solve_bound(cond K_P) + cond(K_P) e_F (first order; the orthonormalization of a frame is as well conditioned as
//! the frame).
inline double deformation_bound(const Mesh& m, const Edit& e, const DeformOptions& o) {
  if (o.method != Method::Lri) return exact::solve_bound(system_condition(m, e, o));
  const LriDeformer d(m, e, o);
  const double frames = exact::solve_bound(exact::condition_number(d.frame_system().K));
  const double positions = exact::condition_number(d.position_system().K);
  return exact::solve_bound(positions) + positions * frames;
}

//! ||a - b||_F / ||b||_F in the normalized coordinates of mesh m (the unknowns of the deformers' systems).
inline double normalized_rel(const Mesh& m, const Points& a, const Points& b) {
  const Normalization unit = Normalization::fit(m.V);
  return exact::rel(unit.apply(a), unit.apply(b));
}

}  // namespace db
