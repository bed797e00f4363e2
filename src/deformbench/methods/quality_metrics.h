#pragma once
//! Quality measures of a deformation result V (#V by 3) against its rest mesh V0 (same faces), and against an
//! analytic ideal where one exists. All are dimensionless: lengths are relative to the rest bounding-box
//! diagonal or to the rest edge lengths, so meshes of any size compare.
#include <optional>
#include <vector>

#include "solvers/base/types.h"
#include "mesh/mesh.h"

namespace db {

struct DistanceStats {
  double rms = 0;  //!< sqrt(mean_i |v_i - r_i|^2) / diag
  double max = 0;  //!< max_i |v_i - r_i| / diag
};
//! Per-vertex distance between two embeddings of the same mesh, relative to `diag` (> 0).
DistanceStats distance_between(const Points& V, const Points& ref, double diag);

//! Relative RMS edge-length distortion: sqrt(mean_e ((|e'| - |e|) / |e|)^2) over the undirected edges.
double edge_length_distortion(const Points& V0, const Points& V, const Adjacency& adj);

//! Best rotation per vertex (ARAP local step, uniform weights): R_i = argmin sum_j |e'_ij - R e_ij|^2 over the
//! 1-ring edges e_ij = x_j - x_i (Kabsch; proper rotations).
std::vector<Mat3> best_fit_rotations(const Points& V0, const Points& V, const Adjacency& adj);

//! ARAP (local rigidity) energy, relative: sum_i sum_j |e'_ij - R_i e_ij|^2 / sum_i sum_j |e_ij|^2 with R_i from
//! best_fit_rotations. 0 for a rigid motion; dimensionless.
double arap_energy(const Points& V0, const Points& V, const Adjacency& adj);

struct AngleStats {
  double mean_deg = 0, max_deg = 0;
};
//! Angle between the area-weighted vertex normals of V and of ref (e.g. the analytic ideal), degrees.
AngleStats normal_deviation(const Points& V, const Points& ref, const Faces& F);
//! Angle between the normal of V and the rest normal carried by the vertex's best-fit rotation R_i n_i: how
//! much a normal tilts relative to the motion of its own 1-ring (0 for any locally rigid motion), degrees.
AngleStats local_normal_deviation(const Points& V0, const Points& V, const Faces& F, const Adjacency& adj);

//! LRI detail error: discrete forms d'_ij of V in its own frames against the rest forms d_ij, both with the
//! "first" frame strategy (a deterministic function of the geometry): sqrt(sum |d' - d|^2 / sum |d|^2).
//! 0 exactly for rigid motions (the forms are rotation invariant).
double lri_detail_error(const Points& V0, const Points& V, const Faces& F, const Adjacency& adj);

//! True when every edge is shared by exactly two faces (a closed 2-manifold surface).
bool is_closed(const Faces& F);
//! Signed enclosed volume (divergence theorem: sum over faces of det(a, b, c) / 6); positive for outward faces.
double signed_volume(const Points& V, const Faces& F);
//! Relative volume change (vol(V) - vol(V0)) / |vol(V0)| for closed meshes; std::nullopt for open meshes (the
//! enclosed volume is undefined; callers print "n/a").
std::optional<double> volume_change(const Points& V0, const Points& V, const Faces& F);

}  // namespace db
