#pragma once
//! Triangle mesh as plain arrays plus the 1-ring adjacency every operator is built from.
#include <string>
#include <vector>

#include "core/types.h"

namespace db {

//! Most vertices or faces a mesh may have (readers, generators and subdivision refuse more): 32-bit indices with
//! room for TF's 3x3 blocks and the systems' index arithmetic.
constexpr long long kMaxElements = 0x7fffffff / 4;

struct Mesh {
  Points V;          //!< #V by 3 positions
  Faces F;           //!< #F by 3 corner indices, counter-clockwise
  std::string name;  //!< for result rows (file stem or generator name)

  int num_vertices() const { return static_cast<int>(V.rows()); }
  int num_faces() const { return static_cast<int>(F.rows()); }
};

//! Vertex 1-rings in compressed form: neighbors of i are nbr[off[i] .. off[i+1]), sorted ascending.
struct Adjacency {
  std::vector<int> off;
  std::vector<int> nbr;

  int num_vertices() const { return static_cast<int>(off.size()) - 1; }
  int degree(int i) const { return off[i + 1] - off[i]; }
  const int* begin(int i) const { return nbr.data() + off[i]; }
  const int* end(int i) const { return nbr.data() + off[i + 1]; }
};

//! 1-ring adjacency from the faces (each undirected edge once per endpoint).
Adjacency vertex_adjacency(const Mesh& mesh);

//! Checks what the deformation operators need and throws InputError naming the first problem:
//! empty mesh, non-finite coordinates, face indices out of range, degenerate faces (repeated corner or zero
//! area relative to the bounding box), non-manifold edges (more than two faces), non-manifold vertices
//! (more than one fan), isolated vertices.
void validate_mesh(const Mesh& mesh);

//! Axis-aligned bounding-box diagonal length.
double bbox_diagonal(const Points& V);

}  // namespace db
