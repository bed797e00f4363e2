// Mesh invariants: adjacency structure and validate_mesh's diagnosis of each kind of broken mesh.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "solvers/base/error.h"
#include "mesh/mesh.h"
#include "mesh/procedural.h"
#include "solvers/tests/worker_threads.h"
#include "test_util.h"

namespace {

using namespace db;

Mesh tetrahedron() {
  Mesh m;
  m.name = "tet";
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  m.F.resize(4, 3);
  m.F << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  return m;
}

// 3x3 vertices, 2x2 quads split along one diagonal: an open mesh with a boundary.
Mesh grid3x3() {
  Mesh m;
  m.name = "grid";
  m.V.resize(9, 3);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) m.V.row(3 * j + i) << i, j, 0;
  m.F.resize(8, 3);
  int f = 0;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const int a = 3 * j + i;
      m.F.row(f++) << a, a + 1, a + 4;
      m.F.row(f++) << a, a + 4, a + 3;
    }
  return m;
}

std::set<std::pair<int, int>> edge_set(const Mesh& m) {
  std::set<std::pair<int, int>> e;
  for (int f = 0; f < m.num_faces(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int a = m.F(f, c), b = m.F(f, (c + 1) % 3);
      e.insert({std::min(a, b), std::max(a, b)});
    }
  return e;
}

void expect_adjacency_consistent(const Mesh& m) {
  const Adjacency adj = vertex_adjacency(m);
  ASSERT_EQ(adj.num_vertices(), m.num_vertices());
  std::set<std::pair<int, int>> seen;
  for (int v = 0; v < adj.num_vertices(); ++v) {
    for (const int* w = adj.begin(v); w != adj.end(v); ++w) {
      EXPECT_NE(*w, v) << "self loop at " << v;
      if (w + 1 != adj.end(v)) {
        EXPECT_LT(*w, *(w + 1)) << "neighbours of " << v << " not strictly sorted";
      }
      // Symmetric: v must appear in the ring of w.
      EXPECT_TRUE(std::binary_search(adj.begin(*w), adj.end(*w), v)) << v << " -> " << *w << " not mirrored";
      seen.insert({std::min(v, *w), std::max(v, *w)});
    }
  }
  EXPECT_EQ(seen, edge_set(m));
  EXPECT_EQ(adj.nbr.size(), 2 * edge_set(m).size());
}

TEST(Adjacency, SymmetricSortedAndMatchesEdges) {
  expect_adjacency_consistent(tetrahedron());
  expect_adjacency_consistent(grid3x3());
  expect_adjacency_consistent(make_cylinder(5, 7, 1.0, 2.0));
  expect_adjacency_consistent(make_bar(2, 3, 4, 1, 1, 3));
}

TEST(Adjacency, SameOnAnyWorkerThreads) {
  // 15000 vertices, 30000 faces: several face and vertex ranges (4096 each at least) on up to four threads.
  const Mesh m = make_cylinder(150, 100, 1.0, 2.0);
  std::vector<Adjacency> got;
  for (int threads : {1, 3, 4}) {
    test::WorkerThreads env(threads);
    expect_adjacency_consistent(m);
    got.push_back(vertex_adjacency(m));
  }
  for (const Adjacency& a : got) {
    EXPECT_EQ(a.off, got[0].off);
    EXPECT_EQ(a.nbr, got[0].nbr);
  }
}

TEST(Adjacency, DegreesOfKnownMeshes) {
  const Adjacency t = vertex_adjacency(tetrahedron());
  for (int v = 0; v < 4; ++v) EXPECT_EQ(t.degree(v), 3);
  const Adjacency g = vertex_adjacency(grid3x3());
  EXPECT_EQ(g.degree(4), 6);  // the interior vertex of a diagonal-split grid
  EXPECT_EQ(std::vector<int>(g.begin(4), g.end(4)), (std::vector<int>{0, 1, 3, 5, 7, 8}));
}

TEST(ValidateMesh, AcceptsGoodMeshes) {
  EXPECT_NO_THROW(validate_mesh(tetrahedron()));
  EXPECT_NO_THROW(validate_mesh(grid3x3()));
  EXPECT_NO_THROW(validate_mesh(make_cylinder(4, 6, 1.0, 1.0)));
}

TEST(ValidateMesh, Empty) {
  expect_input_error([] { validate_mesh(Mesh{}); }, "empty");
  Mesh m = tetrahedron();
  m.F.resize(0, 3);
  expect_input_error([&] { validate_mesh(m); }, "no faces");
}

TEST(ValidateMesh, NonFinite) {
  Mesh m = tetrahedron();
  m.V(2, 1) = std::numeric_limits<double>::quiet_NaN();
  expect_input_error([&] { validate_mesh(m); }, "vertex 2 has a non-finite coordinate");
  m = tetrahedron();
  m.V(3, 0) = std::numeric_limits<double>::infinity();
  expect_input_error([&] { validate_mesh(m); }, "vertex 3 has a non-finite coordinate");
}

TEST(ValidateMesh, IndexOutOfRange) {
  Mesh m = tetrahedron();
  m.F(1, 2) = 7;
  expect_input_error([&] { validate_mesh(m); }, "face 1 has corner index 7 out of range");
  m = tetrahedron();
  m.F(3, 0) = -1;
  expect_input_error([&] { validate_mesh(m); }, "face 3 has corner index -1 out of range");
}

TEST(ValidateMesh, DegenerateFaces) {
  Mesh m = grid3x3();
  m.F(2, 1) = m.F(2, 0);
  expect_input_error([&] { validate_mesh(m); }, "face 2 is degenerate (repeated corner");
  // Collinear corners: zero area.
  Mesh t = tetrahedron();
  t.V.row(3) = 0.5 * (t.V.row(0) + t.V.row(1));  // face 1 (0 1 3) collapses to a segment
  expect_input_error([&] { validate_mesh(t); }, "face 1 is degenerate (area");
}

TEST(ValidateMesh, NonManifoldEdge) {
  Mesh m;
  m.V.resize(5, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1;
  m.F.resize(3, 3);
  m.F << 0, 1, 2, 1, 0, 3, 0, 1, 4;
  expect_input_error([&] { validate_mesh(m); }, "non-manifold edge (0, 1) shared by 3 faces");
}

TEST(ValidateMesh, NonManifoldVertex) {
  // Two fans touching at vertex 0 only (a bow tie), each fan two triangles.
  Mesh m;
  m.V.resize(7, 3);
  m.V << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, -1, 0, 0, -1, -1, 0, 0, -1, 0;
  m.F.resize(4, 3);
  m.F << 0, 1, 2, 0, 2, 3, 0, 4, 5, 0, 5, 6;
  expect_input_error([&] { validate_mesh(m); }, "non-manifold vertex 0");
}

TEST(ValidateMesh, ClosedFanIsManifold) {
  // A vertex whose faces close into a cycle (interior vertex) and one on an open fan (boundary) are both fine.
  Mesh c = make_cylinder(3, 5, 1.0, 1.0);
  EXPECT_NO_THROW(validate_mesh(c));
}

TEST(ValidateMesh, IsolatedVertex) {
  Mesh m = tetrahedron();
  m.V.conservativeResize(5, 3);
  m.V.row(4) << 2, 2, 2;
  expect_input_error([&] { validate_mesh(m); }, "vertex 4 is isolated");
}

TEST(ValidateMesh, MessageNamesTheMesh) {
  Mesh m = tetrahedron();
  m.name = "my_model";
  m.V(0, 0) = std::nan("");
  expect_input_error([&] { validate_mesh(m); }, "my_model");
}

TEST(BboxDiagonal, UnitCubeAndEmpty) {
  Points V(2, 3);
  V << 0, 0, 0, 1, 1, 1;
  EXPECT_DOUBLE_EQ(bbox_diagonal(V), std::sqrt(3.0));
  EXPECT_EQ(bbox_diagonal(Points(0, 3)), 0.0);
  EXPECT_DOUBLE_EQ(bbox_diagonal(grid3x3().V), std::sqrt(8.0));
}

}  // namespace
