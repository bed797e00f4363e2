#pragma once
//! Zippering two boundary loops into one surface (transplanting's join): the band between an outer loop (the
//! hole cut into the target) and an inner loop (the grafted patch's boundary) is triangulated by walking both
//! loops at once in the order of their parameter angle (their normalized arc length in the common disk
//! parameterization): each step closes the edge whose far end comes first, so every triangle spans one loop edge
//! and the nearest vertex of the other loop. Where the hole's loop is a staircase (an edge running inwards), the
//! triangle that order picks can fold over in space. Given positions and the outer loop's normals, the zipper
//! instead closes the edge whose new diagonal is shorter (Fuchs et al. 1977's greedy), and takes the other
//! candidate when that one folds (faces against the normal) and the other does not. Hand-written: a merge of two sorted sequences; CGAL's hole filling
//! would retriangulate the band without the correspondence the shared parameterization already gives.
#include <vector>

#include "solvers/base/types.h"

namespace db {

//! One zipper loop: vertex ids (in the joined mesh) in the order of increasing parameter angle, the first at
//! angle 0, and their angles in [0, 2 pi).
struct ZipperLoop {
  std::vector<int> ids;
  std::vector<double> angle;
  Points at;      //!< optional: positions (a row per id), to avoid folds
  Points normal;  //!< optional, the outer loop's: the surface normal at each vertex
};

//! The band's m_outer + m_inner triangles, counter-clockwise when the loops run counter-clockwise around the
//! disk (outer at the larger radius): they use each outer edge (a, b) as a -> b and each inner edge (a, b) as
//! b -> a, so they join the faces outside the outer loop and inside the inner one into one oriented manifold.
//! \throw InputError for an empty loop or mismatched ids and angles.
Faces zipper_band(const ZipperLoop& outer, const ZipperLoop& inner);

}  // namespace db
