#pragma once
//! The mesh and edit that `deformbench advise --predict-only --scale K` predicts for: the user's mesh Loop-subdivided
//! to about K times its vertices, with the edit's roles carried over. Why: the factor's size and flops at K times
//! the vertices depend on the ordering (AMD's fill grows faster than nested dissection's) and on the mesh's shape;
//! the symbolic analysis of the subdivided mesh counts them instead of a growth law assuming one of them.
#include "edit/edit.h"
#include "mesh/mesh.h"

namespace db {

struct ScaledEdit {
  Mesh mesh;
  Edit edit;
  int levels = 0;       //!< rounds of Loop subdivision (each about 4x the vertices)
  double residual = 1;  //!< the scale left for the growth law (run_prediction.h), in [1/2, 2] when levels allow
};

//! Most vertices a subdivided mesh may have: the predictor's analysis of a larger one takes minutes and gigabytes.
constexpr double kMaxScaledVertices = 4e6;

//! log4(scale) rounded, fewer where a mesh of `num_vertices` subdivided that often would exceed kMaxScaledVertices.
int scale_levels(int num_vertices, double scale);

//! The mesh subdivided scale_levels times; residual = scale / 4^levels. A vertex on an edge between two vertices of
//! one role takes that role, any other new vertex is free (a handle or a fixed region keeps its area). The edit's
//! targets (per-vertex drags) are dropped: a prediction needs the roles only.
//! \throw InputError as loop_subdivide, or for scale < 1.
ScaledEdit scale_edit(const Mesh& mesh, const Edit& edit, double scale);

}  // namespace db
