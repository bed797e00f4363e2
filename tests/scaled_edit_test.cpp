// methods/scaled_edit.h: the subdivision levels chosen for a scale, and the roles carried to the new vertices,
// counted independently from the coarse mesh's edges.
#include <cmath>
#include <set>
#include <utility>

#include <gtest/gtest.h>

#include "methods/scaled_edit.h"
#include "mesh/procedural.h"
#include "solvers/base/error.h"

namespace db {
namespace {

//! A bar with its lowest vertices fixed and its highest the handle.
Edit bar_edit(const Mesh& m) {
  Edit e;
  e.name = "bar";
  e.roles.assign(static_cast<std::size_t>(m.num_vertices()), Role::Free);
  for (int v = 0; v < m.num_vertices(); ++v)
    e.roles[v] = m.V(v, 2) < 0.3 ? Role::Fixed : m.V(v, 2) > 0.7 ? Role::Handle : Role::Free;
  return e;
}

//! Edges of `m` whose two ends both have `role`.
int edges_within(const Mesh& m, const Edit& e, Role role) {
  std::set<std::pair<int, int>> edges;
  for (int f = 0; f < m.num_faces(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int a = m.F(f, c), b = m.F(f, (c + 1) % 3);
      if (e.roles[a] == role && e.roles[b] == role) edges.insert({std::min(a, b), std::max(a, b)});
    }
  return static_cast<int>(edges.size());
}

TEST(ScaleEdit, OneLevelPerFourTimesTheVerticesAndTheRestByTheGrowthLaw) {
  const Mesh m = make_bar(3, 3, 6, 1, 1, 1);
  const Edit e = bar_edit(m);
  EXPECT_EQ(scale_edit(m, e, 1).levels, 0);
  EXPECT_EQ(scale_edit(m, e, 1).mesh.num_vertices(), m.num_vertices());
  EXPECT_EQ(scale_edit(m, e, 4).levels, 1);
  EXPECT_EQ(scale_edit(m, e, 4).residual, 1);
  EXPECT_EQ(scale_edit(m, e, 2.5).levels, 1);  // log4 2.5 = 0.66 rounds to 1
  EXPECT_EQ(scale_edit(m, e, 2.5).residual, 2.5 / 4);
  EXPECT_EQ(scale_edit(m, e, 16).levels, 2);
  const int n = 100000;  // may be subdivided twice (1.6M vertices), not three times (6.4M: over the limit)
  ASSERT_GT(n * std::pow(4.0, 3), kMaxScaledVertices);
  ASSERT_LE(n * std::pow(4.0, 2), kMaxScaledVertices);
  EXPECT_EQ(scale_levels(n, 16), 2);
  EXPECT_EQ(scale_levels(n, 64), 2);
  EXPECT_EQ(scale_levels(n, 1e4), 2);
  EXPECT_THROW(scale_levels(n, 0.5), InputError);
  EXPECT_THROW(scale_edit(m, e, 0.5), InputError);
}

TEST(ScaleEdit, ANewVertexTakesTheRoleItsEdgesEndsShareElseItIsFree) {
  const Mesh m = make_bar(3, 3, 6, 1, 1, 1);
  const Edit e = bar_edit(m);
  const ScaledEdit s = scale_edit(m, e, 4);
  ASSERT_EQ(s.edit.roles.size(), static_cast<std::size_t>(s.mesh.num_vertices()));
  for (int v = 0; v < m.num_vertices(); ++v) EXPECT_EQ(s.edit.roles[v], e.roles[v]);  // the old vertices keep theirs
  for (Role r : {Role::Fixed, Role::Handle}) {
    const int added = edges_within(m, e, r);
    ASSERT_GT(added, 0);
    EXPECT_EQ(s.edit.count(r), e.count(r) + added);
  }
  EXPECT_EQ(s.edit.count(Role::Free) + s.edit.count(Role::Fixed) + s.edit.count(Role::Handle), s.mesh.num_vertices());
}

}  // namespace
}  // namespace db
