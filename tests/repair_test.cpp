// Real-world meshes (issue 13, item 4): non-manifold meshes deform with uniform LAP and TF (with a warning);
// cotan weights and LRI refuse them naming `meshtool repair`; repair_mesh turns fins, pinched vertices,
// duplicate and degenerate faces and isolated vertices into a valid manifold that cotan and LRI accept.
#include <gtest/gtest.h>

#include <array>
#include <map>
#include <numeric>
#include <string>

#include "solvers/base/error.h"
#include "edit/edit.h"
#include "mesh/mesh.h"
#include "mesh/procedural.h"
#include "mesh/repair.h"
#include "methods/deformer.h"

namespace db {
namespace {

// Builds meshes from grid sheets glued where their vertices coincide exactly.
class Soup {
 public:
  //! An nx x ny grid of unit cells from `o` along ex and ey, two triangles a cell, counter-clockwise about ex x ey.
  Soup& sheet(int nx, int ny, Vec3 o, Vec3 ex, Vec3 ey) {
    auto id = [&](int i, int j) { return vertex(o + i * ex + j * ey); };
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        face(id(i, j), id(i + 1, j), id(i + 1, j + 1));
        face(id(i, j), id(i + 1, j + 1), id(i, j + 1));
      }
    return *this;
  }
  int vertex(const Vec3& p) {
    const auto [it, added] = ids_.emplace(std::array<double, 3>{p.x(), p.y(), p.z()}, static_cast<int>(xyz_.size()));
    if (added) xyz_.push_back(p);
    return it->second;
  }
  Soup& face(int a, int b, int c) {
    faces_.push_back({a, b, c});
    return *this;
  }
  Mesh mesh() const {
    Mesh m;
    m.name = "soup";
    m.V.resize(static_cast<Eigen::Index>(xyz_.size()), 3);
    for (std::size_t i = 0; i < xyz_.size(); ++i) m.V.row(static_cast<Eigen::Index>(i)) = xyz_[i].transpose();
    m.F.resize(static_cast<Eigen::Index>(faces_.size()), 3);
    for (std::size_t f = 0; f < faces_.size(); ++f)
      m.F.row(static_cast<Eigen::Index>(f)) << faces_[f][0], faces_[f][1], faces_[f][2];
    return m;
  }

 private:
  std::map<std::array<double, 3>, int> ids_;
  std::vector<Vec3> xyz_;
  std::vector<std::array<int, 3>> faces_;
};

const Vec3 X(1, 0, 0), Y(0, 1, 0), Z(0, 0, 1);

// A 6 x 6 sheet in z = 0 with a vertical fin (6 x 2) standing on its row y = 3: six edges with three faces.
Soup finned() { return std::move(Soup().sheet(6, 6, Vec3(0, 0, 0), X, Y).sheet(6, 2, Vec3(0, 3, 0), X, Z)); }

// The finned sheet plus a 3 x 3 sheet touching it only at the corner (6, 6, 0): a pinched vertex.
Soup finned_and_pinched() { return std::move(finned().sheet(3, 3, Vec3(6, 6, 0), X, Y)); }

// The message of the InputError f() throws ("" if it throws none).
template <class F>
std::string input_error(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// Fixed: x < 1.5 and x > 7.5; handle: 4.5 < x < 6.5; every piece the repair leaves (sheet, fin, corner sheet)
// holds fixed and handle vertices not on one line.
Edit edit_by_x(const Mesh& m) {
  Edit e;
  e.name = "by_x";
  e.roles.assign(m.num_vertices(), Role::Free);
  for (int v = 0; v < m.num_vertices(); ++v) {
    const double x = m.V(v, 0);
    if (x < 1.5 || x > 7.5) e.roles[v] = Role::Fixed;
    if (x > 4.5 && x < 6.5) e.roles[v] = Role::Handle;
  }
  e.transform.topRightCorner<3, 1>() = Vec3(0, 0, 0.5);
  return e;
}

DeformOptions method(const std::string& name, Weights w = Weights::Uniform) {
  DeformOptions o;
  o.method = parse_enum<Method>(name);
  o.weights = w;
  return o;
}

void expect_deforms(const Mesh& m, const DeformOptions& o) {
  const Edit e = edit_by_x(m);
  const auto d = make_deformer(m, e, o);
  const Points out = d->deform(e.transform);
  ASSERT_TRUE(out.allFinite());
  for (int v = 0; v < m.num_vertices(); ++v) {
    if (e.roles[v] == Role::Free) continue;
    const double dz = e.roles[v] == Role::Handle ? 0.5 : 0.0;
    EXPECT_NEAR(out(v, 2), m.V(v, 2) + dz, 1e-9) << "constrained vertex " << v;
  }
}

TEST(NonManifold, FoundAndCounted) {
  const Mesh m = finned_and_pinched().mesh();
  const NonManifold nm = find_non_manifold(m);
  ASSERT_EQ(nm.edges.size(), 6u);
  for (const auto& e : nm.edges) EXPECT_EQ(e.faces, 3);
  ASSERT_EQ(nm.vertices.size(), 1u);
  EXPECT_EQ(m.V.row(nm.vertices[0].v), Eigen::RowVector3d(6, 6, 0));
  EXPECT_EQ(nm.vertices[0].fans, 2);
  EXPECT_NE(nm.summary().find("6 non-manifold edges"), std::string::npos) << nm.summary();
  EXPECT_NE(nm.summary().find("1 non-manifold vertex"), std::string::npos) << nm.summary();
  EXPECT_NO_THROW(validate_mesh(m, Manifold::Allowed));
  EXPECT_NE(input_error([&] { validate_mesh(m); }).find("meshtool repair"), std::string::npos);
  EXPECT_TRUE(find_non_manifold(make_cylinder(4, 6, 1, 1)).empty());
}

TEST(NonManifold, UniformLapAndTfDeformItWithAWarning) {
  const Mesh m = finned_and_pinched().mesh();
  for (const char* name : {"lap", "tf"}) {
    ::testing::internal::CaptureStderr();
    expect_deforms(m, method(name));
    const std::string err = ::testing::internal::GetCapturedStderr();
    EXPECT_NE(err.find("warning"), std::string::npos) << err;
    EXPECT_NE(err.find("6 non-manifold edges"), std::string::npos) << err;
    EXPECT_NE(err.find("1 non-manifold vertex"), std::string::npos) << err;
  }
}

TEST(NonManifold, CotanAndLriRefuseItNamingTheRepair) {
  const Mesh m = finned_and_pinched().mesh();
  const Edit e = edit_by_x(m);
  for (const DeformOptions& o : {method("lap", Weights::Cotan), method("tf", Weights::Cotan), method("lri")}) {
    const std::string msg = input_error([&] { make_deformer(m, e, o); });
    EXPECT_NE(msg.find("meshtool repair"), std::string::npos) << o.method << ": " << msg;
    EXPECT_NE(msg.find("6 non-manifold edges"), std::string::npos) << msg;
  }
}

TEST(Repair, FinComesOffAndTheSheetStaysWhole) {
  const Mesh m = finned().mesh();
  RepairReport r;
  const Mesh out = repair_mesh(m, r);
  EXPECT_NO_THROW(validate_mesh(out));
  EXPECT_EQ(r.non_manifold.edges.size(), 6u);
  // The seven vertices of the shared row get one copy each, for the fin.
  ASSERT_EQ(r.splits.size(), 7u);
  for (const auto& s : r.splits) {
    EXPECT_EQ(m.V(s.vertex, 1), 3.0);
    EXPECT_EQ(s.copies.size(), 1u);
    EXPECT_EQ(out.V.row(s.copies[0]), m.V.row(s.vertex));
  }
  EXPECT_EQ(out.num_vertices(), m.num_vertices() + 7);
  EXPECT_EQ(out.num_faces(), m.num_faces());
  EXPECT_EQ(count_components(out), 2);  // the sheet (whole) and the fin
  // The report names the piece that came off (issue 28): the fin's 24 faces, from the one input component.
  EXPECT_EQ(r.components_before, 1);
  EXPECT_EQ(r.components_after, 2);
  ASSERT_EQ(r.detached.size(), 1u);
  EXPECT_EQ(r.detached[0].faces, 24);
  EXPECT_EQ(r.detached[0].from, 0);
  EXPECT_EQ(r.detached[0].from_kept, m.num_faces() - 24);
  EXPECT_NE(r.summary().find("detached 1 pieces (1 connected components before, 2 after)"), std::string::npos)
      << r.summary();
  EXPECT_TRUE(r.degenerate_faces.empty() && r.duplicate_faces.empty() && r.isolated_vertices.empty());
}

TEST(Repair, FourFacesOnOneEdge) {
  // Two fins on the same row, one up and one down, oriented alike: each row edge has four faces; the sheet stays
  // whole and the fins join into one vertical sheet.
  const Mesh m = std::move(finned().sheet(6, 2, Vec3(6, 3, 0), -X, -Z)).mesh();
  ASSERT_EQ(find_non_manifold(m).edges.front().faces, 4);
  RepairReport r;
  const Mesh out = repair_mesh(m, r);
  EXPECT_NO_THROW(validate_mesh(out));
  EXPECT_EQ(count_components(out), 2);
}

TEST(Repair, PinchedVertexIsSplit) {
  const Mesh m = std::move(Soup().sheet(3, 3, Vec3(0, 0, 0), X, Y).sheet(3, 3, Vec3(3, 3, 0), X, Y)).mesh();
  RepairReport r;
  const Mesh out = repair_mesh(m, r);
  EXPECT_NO_THROW(validate_mesh(out));
  ASSERT_EQ(r.non_manifold.vertices.size(), 1u);
  ASSERT_EQ(r.splits.size(), 1u);
  EXPECT_EQ(r.splits[0].vertex, r.non_manifold.vertices[0].v);
  EXPECT_EQ(out.num_vertices(), m.num_vertices() + 1);
  EXPECT_EQ(count_components(out), 2);
}

TEST(Repair, DuplicateFacesDropped) {
  const Mesh clean = make_cylinder(4, 6, 1.0, 2.0);
  Mesh m = clean;
  const int nf = m.num_faces();
  m.F.conservativeResize(nf + 2, 3);
  m.F.row(nf) = clean.F.row(3);                                             // the same face again
  m.F.row(nf + 1) << clean.F(5, 2), clean.F(5, 1), clean.F(5, 0);           // reversed
  RepairReport r;
  const Mesh out = repair_mesh(m, r);
  ASSERT_EQ(r.duplicate_faces.size(), 2u);
  EXPECT_EQ(r.duplicate_faces[0], std::make_pair(nf, 3));
  EXPECT_EQ(r.duplicate_faces[1], std::make_pair(nf + 1, 5));
  EXPECT_TRUE(r.splits.empty());
  EXPECT_EQ(out.V, clean.V);
  EXPECT_EQ(out.F, clean.F);
}

TEST(Repair, DegenerateFacesAndIsolatedVerticesDropped) {
  const Mesh clean = make_cylinder(4, 6, 1.0, 2.0);
  Mesh m = clean;
  const int nv = m.num_vertices(), nf = m.num_faces();
  // Vertex nv: the midpoint of edge (0, 1), used only by a zero-area face; vertex nv + 1: in no face at all.
  m.V.conservativeResize(nv + 2, 3);
  m.V.row(nv) = 0.5 * (clean.V.row(0) + clean.V.row(1));
  m.V.row(nv + 1) << 5, 5, 5;
  m.F.conservativeResize(nf + 2, 3);
  m.F.row(nf) << 0, nv, 1;  // collinear corners
  m.F.row(nf + 1) << 2, 2, 3;  // repeated corner
  RepairReport r;
  const Mesh out = repair_mesh(m, r);
  ASSERT_EQ(r.degenerate_faces.size(), 2u);
  EXPECT_EQ(r.degenerate_faces[0].first, nf);
  EXPECT_NE(r.degenerate_faces[0].second.find("area"), std::string::npos);
  EXPECT_NE(r.degenerate_faces[1].second.find("repeated corner"), std::string::npos);
  EXPECT_EQ(r.isolated_vertices, (std::vector<int>{nv, nv + 1}));
  EXPECT_EQ(r.vertex_map[nv], -1);
  EXPECT_EQ(r.vertex_map[3], 3);
  EXPECT_EQ(out.V, clean.V);
  EXPECT_EQ(out.F, clean.F);
  EXPECT_NE(r.summary().find("dropped 2 degenerate faces"), std::string::npos) << r.summary();
  EXPECT_NE(r.summary().find("removed 2 isolated vertices"), std::string::npos) << r.summary();
}

TEST(Repair, IsolatedVertexFirstRenumbersTheRest) {
  const Mesh clean = make_cylinder(4, 6, 1.0, 2.0);
  Mesh m;
  m.V.resize(clean.num_vertices() + 1, 3);
  m.V.row(0) << 9, 9, 9;
  m.V.bottomRows(clean.num_vertices()) = clean.V;
  m.F = clean.F.array() + 1;
  RepairReport r;
  const Mesh out = repair_mesh(m, r);
  EXPECT_EQ(r.isolated_vertices, std::vector<int>{0});
  EXPECT_EQ(r.vertex_map[1], 0);
  EXPECT_EQ(out.V, clean.V);
  EXPECT_EQ(out.F, clean.F);
}

TEST(Repair, CleanMeshUnchanged) {
  for (const Mesh& clean : {make_cylinder(5, 7, 1.0, 2.0), make_bar(2, 3, 4, 1, 1, 2), make_bumpy_plane(4, 5, 1, 0.1, 1)}) {
    RepairReport r;
    const Mesh out = repair_mesh(clean, r);
    EXPECT_FALSE(r.changed());
    EXPECT_EQ(r.summary(), "no change");
    EXPECT_TRUE(r.details(0).empty());
    EXPECT_EQ(out.V, clean.V);
    EXPECT_EQ(out.F, clean.F);
  }
}

TEST(Repair, NothingLeftIsAnInputError) {
  Mesh m;
  m.V.resize(3, 3);
  m.V << 0, 0, 0, 1, 0, 0, 2, 0, 0;
  m.F.resize(1, 3);
  m.F << 0, 1, 2;
  RepairReport r;
  EXPECT_NE(input_error([&] { repair_mesh(m, r); }).find("no face is left"), std::string::npos);
  m.F << 0, 1, 3;
  EXPECT_NE(input_error([&] { repair_mesh(m, r); }).find("out of range"), std::string::npos);
}

TEST(Repair, EveryDefectAtOnceThenCotanAndLriAccept) {
  Soup s = finned_and_pinched();
  const int extra = s.vertex(Vec3(20, 20, 20));  // isolated
  s.face(1, 2, 0).face(3, 3, 4);                 // a duplicate of the first face (0 1 2), a repeated corner
  const Mesh m = s.mesh();
  RepairReport r;
  const Mesh out = repair_mesh(m, r);
  EXPECT_EQ(r.duplicate_faces.size(), 1u);
  EXPECT_EQ(r.degenerate_faces.size(), 1u);
  EXPECT_EQ(r.isolated_vertices, std::vector<int>{extra});
  EXPECT_FALSE(r.splits.empty());
  ASSERT_NO_THROW(validate_mesh(out));
  EXPECT_EQ(count_components(out), 3);  // sheet, fin, corner sheet
  for (const auto& line : r.details(0)) EXPECT_FALSE(line.empty());
  expect_deforms(out, method("lap", Weights::Cotan));
  expect_deforms(out, method("tf", Weights::Cotan));
  expect_deforms(out, method("lri"));
}

}  // namespace
}  // namespace db
