#pragma once
//! Triangle mesh as plain arrays plus the 1-ring adjacency every operator is built from.
#include <string>
#include <vector>

#include "solvers/base/types.h"

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

//! The faces around each vertex in the same compressed form (face ids ascending; a face with a repeated corner
//! is listed once per corner). Face indices must be in range.
Adjacency vertex_faces(const Mesh& mesh);

//! Throws InputError naming the first non-finite coordinate or face index out of range.
void check_arrays(const Mesh& mesh);

//! Non-manifold elements of a mesh: edges shared by more than two faces, and vertices whose faces form more
//! than one fan (a pinched vertex: two cones touching at their tips).
struct NonManifold {
  struct Edge {
    int a, b, faces;  //!< a < b
  };
  struct Vertex {
    int v, faces, fans;
  };
  std::vector<Edge> edges;
  std::vector<Vertex> vertices;

  bool empty() const { return edges.empty() && vertices.empty(); }
  //! "2 non-manifold edges (first: (0, 1) shared by 3 faces) and 1 non-manifold vertex (first: 5, 8 faces in 2 fans)"
  std::string summary() const;
};

//! The connected component of each face (faces sharing a vertex are connected), numbered 0, 1, ... in the order
//! of their first face; the count is the largest label + 1.
std::vector<int> face_components(const Mesh& mesh);
//! How many components face_components finds.
int count_components(const Mesh& mesh);

//! Every non-manifold edge and vertex, in ascending order. Face indices must be in range (validate_mesh checks
//! them first). O(F log valence).
NonManifold find_non_manifold(const Mesh& mesh);

//! Why face f is degenerate, or "" when it is not: a repeated corner, or an area under 1e-14 of the squared
//! bounding-box diagonal `diag` (computed on coordinates divided by diag, so neither tiny nor huge models under-
//! or overflow).
std::string degenerate_face(const Mesh& mesh, int f, double diag);

//! Whether validate_mesh insists on a 2-manifold. Uniform LAP and TF are defined on the vertex graph and accept
//! non-manifold edges and vertices; cotan weights and LRI need a manifold 1-ring around every vertex.
enum class Manifold { Required, Allowed };

//! Checks what the deformation operators need and throws InputError naming the first problem:
//! empty mesh, non-finite coordinates, face indices out of range, degenerate faces (degenerate_face),
//! isolated vertices, and with Manifold::Required non-manifold edges and vertices. Messages for what
//! `meshtool repair` fixes (degenerate faces, isolated vertices, non-manifold elements) name it.
void validate_mesh(const Mesh& mesh, Manifold manifold = Manifold::Required);

//! Axis-aligned bounding-box diagonal length.
double bbox_diagonal(const Points& V);

//! bbox_diagonal of finite coordinates, checked to serve as the unit the deformers scale by: finite, and zero or
//! at least the smallest normal double (its inverse finite). \throw InputError naming the vertices and the axis
//! otherwise: a mesh spanning more than a double can measure, or so small that its coordinates keep too few digits.
double checked_bbox_diagonal(const Points& V);

}  // namespace db
