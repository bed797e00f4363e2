// Edits: roles, validation, Botsch-Sorkine readers, index lists, selections, transform specs, .edit case files.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include <Eigen/Geometry>

#include "solvers/base/error.h"
#include "edit/edit.h"
#include "edit/edit_io.h"
#include "edit/selection.h"
#include "edit/transform.h"
#include "mesh/mesh_io.h"
#include "mesh/procedural.h"
#include "test_util.h"

namespace {

using namespace db;
namespace fs = std::filesystem;

const std::string kBs08 = bs08_dir().string();

class EditFiles : public TempDirTest {};

// 5x5 vertex grid in the z = 0 plane, vertex (i, j) at (i, j, 0) with index 5 j + i.
Mesh grid5() {
  Mesh m = make_bumpy_plane(4, 4, 4.0, 0.0, 0);
  m.V.col(0).array() += 2.0;
  m.V.col(1).array() += 2.0;
  return m;
}

Edit small_edit(int nv) {
  Edit e;
  e.name = "small";
  e.roles.assign(nv, Role::Free);
  e.roles[0] = Role::Fixed;
  e.roles[nv - 1] = Role::Handle;
  return e;
}

TEST(Edit, CountAndVertices) {
  Edit e;
  e.roles = {Role::Fixed, Role::Handle, Role::Free, Role::Handle, Role::Fixed};
  EXPECT_EQ(e.count(Role::Fixed), 2);
  EXPECT_EQ(e.count(Role::Free), 1);
  EXPECT_EQ(e.count(Role::Handle), 2);
  EXPECT_EQ(e.vertices(Role::Handle), (std::vector<int>{1, 3}));
  EXPECT_EQ(e.vertices(Role::Fixed), (std::vector<int>{0, 4}));
}

TEST(ValidateEdit, AcceptsAndRejects) {
  const Mesh m = grid5();
  EXPECT_NO_THROW(validate_edit(m, small_edit(m.num_vertices())));

  Edit e = small_edit(3);
  expect_input_error([&] { validate_edit(m, e); }, "selection has 3 entries but the mesh has 25 vertices");
  e = small_edit(m.num_vertices());
  e.roles.back() = Role::Free;
  expect_input_error([&] { validate_edit(m, e); }, "handle is empty");
  e = small_edit(m.num_vertices());
  e.transform(0, 3) = std::numeric_limits<double>::quiet_NaN();
  expect_input_error([&] { validate_edit(m, e); }, "non-finite");
  e = small_edit(m.num_vertices());
  e.transform(3, 0) = 0.5;
  expect_input_error([&] { validate_edit(m, e); }, "not affine");
  e = small_edit(m.num_vertices());
  for (auto& r : e.roles)
    if (r == Role::Free) r = Role::Fixed;
  expect_input_error([&] { validate_edit(m, e); }, "no free vertex");
}

TEST(Bs08, ReadSelDefAndLoadEveryCase) {
  ASSERT_TRUE(fs::exists(kBs08)) << kBs08 << " is missing: the BS08 edits are bundled in data/bs08";
  for (const std::string& name : kBs08Cases) {
    SCOPED_TRACE(name);
    const std::string stem = kBs08 + "/" + name;
    const Mesh m = read_mesh(stem + ".off");
    const std::vector<Role> roles = read_sel(stem + ".sel", m.num_vertices());
    ASSERT_EQ(static_cast<int>(roles.size()), m.num_vertices());
    Edit e;
    e.roles = roles;
    EXPECT_GT(e.count(Role::Fixed), 0);
    EXPECT_GT(e.count(Role::Free), 0);
    EXPECT_GT(e.count(Role::Handle), 0);
    const Mat4 T = read_def(stem + ".def");
    EXPECT_EQ(T.row(3), Eigen::RowVector4d(0, 0, 0, 1));
    // The files print 6 decimals: the linear part is a rotation to that precision.
    const Mat3 R = T.topLeftCorner<3, 3>();
    EXPECT_LT((R.transpose() * R - Mat3::Identity()).norm(), 1e-5);
    EXPECT_NEAR(R.determinant(), 1.0, 1e-5);

    const EditCase c = load_edit_case(stem);
    EXPECT_EQ(c.edit.name, name);
    EXPECT_EQ(c.edit.roles, roles);
    EXPECT_EQ(c.edit.transform, T);
    EXPECT_EQ(c.mesh_path, stem + ".off");
    EXPECT_EQ(c.mesh.V, m.V);
    EXPECT_EQ(read_bs08_edit(stem + ".sel", stem + ".def", m.num_vertices()).roles, roles);
  }
  expect_input_error([&] { read_sel(kBs08 + "/bar.sel", 17); }, "but the mesh has 17 vertices");
}

TEST_F(EditFiles, ReadSelErrors) {
  EXPECT_EQ(read_sel(write("a.sel", "# c\n0\n1 # x\n\n2\n"), 3), (std::vector<Role>{Role::Fixed, Role::Free, Role::Handle}));
  EXPECT_EQ(read_sel(path("a.sel"), -1).size(), 3u);  // count check disabled
  expect_input_error([&] { read_sel(path("a.sel"), 4); }, "selection has 3 entries but the mesh has 4 vertices");
  expect_input_error([&] { read_sel(write("b.sel", "0\n3\n1\n"), 3); }, "b.sel: line 2: invalid status '3'");
  expect_input_error([&] { read_sel(write("c.sel", "0\n1 2\n"), 3); }, "line 2: invalid status '1 2'");
  expect_input_error([&] { read_sel(write("d.sel", "0\nx\n"), 2); }, "invalid status 'x'");
  expect_input_error([&] { read_sel(path("missing.sel"), 2); }, "cannot open selection file");
}

TEST_F(EditFiles, ReadDefErrors) {
  const Mat4 T = read_def(write("a.def", "# m\n1 0 0 1.5\n0 1 0 0\n0 0 1 0\n0 0 0 1\n"));
  EXPECT_EQ(T(0, 3), 1.5);
  expect_input_error([&] { read_def(write("b.def", "1 0 0 0\n0 1 0 0\n0 0 1 0\n")); }, "expected 4 matrix rows, got 3");
  expect_input_error([&] { read_def(write("c.def", "1 0 0 0 0\n")); }, "line 1: expected 4 numbers");
  expect_input_error([&] { read_def(write("d.def", "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 1 1\n")); }, "not an affine");
  expect_input_error([&] { read_def(write("e.def", "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n1 0 0 0\n")); },
                     "line 5: unexpected content");
  expect_input_error([&] { read_def(write("f.def", "1 0 0 0\n0 y 0 0\n0 0 1 0\n0 0 0 1\n")); }, "line 2: bad number 'y'");
  expect_input_error([&] { read_def(path("none.def")); }, "cannot open transform file");
}

TEST_F(EditFiles, IndexListsAndEditFromLists) {
  EXPECT_EQ(read_index_list(write("a.txt", "1, 2 3\n# comment 9\n4,5,\n\n")), (std::vector<int>{1, 2, 3, 4, 5}));
  expect_input_error([&] { read_index_list(write("b.txt", "1 2\n3 x\n")); }, "b.txt: line 2: 'x' is not a vertex index");
  expect_input_error([&] { read_index_list(write("c.txt", "-3\n")); }, "line 1: vertex index -3 out of range");

  const Mat4 T = translation(Vec3(0, 0, 1));
  const Edit e = edit_from_lists(6, {1, 2, 3, 4}, {4, 3}, T);
  EXPECT_EQ(e.roles, (std::vector<Role>{Role::Fixed, Role::Free, Role::Free, Role::Handle, Role::Handle, Role::Fixed}));
  EXPECT_EQ(e.transform, T);
  expect_input_error([&] { edit_from_lists(20, {1, 2}, {2, 17}, T); }, "handle vertex 17 is outside the region of interest");
  expect_input_error([&] { edit_from_lists(6, {1, 6}, {1}, T); }, "region-of-interest vertex 6 out of range");
  expect_input_error([&] { edit_from_lists(6, {1}, {-1}, T); }, "handle vertex -1 out of range");
  expect_input_error([&] { edit_from_lists(6, {1}, {}, T); }, "handle is empty");
}

TEST(Selection, SphereBoxKRingNearest) {
  const Mesh m = grid5();
  EXPECT_EQ(select_sphere(m, Vec3(0, 0, 0), 1.0), (std::vector<int>{0, 1, 5}));
  EXPECT_EQ(select_sphere(m, Vec3(2, 2, 0), 0.5), (std::vector<int>{12}));
  EXPECT_TRUE(select_sphere(m, Vec3(9, 9, 9), 1.0).empty());
  EXPECT_EQ(select_box(m, Vec3(3, 3, -1), Vec3(4, 4, 1)), (std::vector<int>{18, 19, 23, 24}));
  EXPECT_EQ(select_box(m, Vec3(0, 4, 0), Vec3(4, 4, 0)), (std::vector<int>{20, 21, 22, 23, 24}));

  const Adjacency adj = vertex_adjacency(m);
  EXPECT_EQ(select_k_ring(adj, 12, 0), (std::vector<int>{12}));
  std::vector<int> ring1(adj.begin(12), adj.end(12));
  ring1.push_back(12);
  std::sort(ring1.begin(), ring1.end());
  EXPECT_EQ(select_k_ring(adj, 12, 1), ring1);
  EXPECT_EQ(select_k_ring(adj, 0, 100).size(), 25u);
  expect_input_error([&] { select_k_ring(adj, 25, 1); }, "seed vertex 25 out of range");
  expect_input_error([&] { select_k_ring(adj, 0, -1); }, "k must be >= 0");

  EXPECT_EQ(select_nearest(m, Vec3(4.1, 4.2, 0), 1), (std::vector<int>{24}));
  // Four vertices tie at distance 1 from (2,2): the lower ids win, deterministically.
  EXPECT_EQ(select_nearest(m, Vec3(2, 2, 0), 3), (std::vector<int>{7, 11, 12}));
  EXPECT_EQ(select_nearest(m, Vec3(0, 0, 0), 25).size(), 25u);
  expect_input_error([&] { select_nearest(m, Vec3(0, 0, 0), 26); }, "count 26");
  expect_input_error([&] { select_nearest(m, Vec3(0, 0, 0), 0); }, "count 0");
}

TEST(Selection, BySpec) {
  const Mesh m = grid5();
  EXPECT_EQ(select_by_spec(m, "all").size(), 25u);
  EXPECT_EQ(select_by_spec(m, "sphere:0,0,0,1"), select_sphere(m, Vec3(0, 0, 0), 1));
  EXPECT_EQ(select_by_spec(m, "box:3,3,-1,4,4,1"), select_box(m, Vec3(3, 3, -1), Vec3(4, 4, 1)));
  EXPECT_EQ(select_by_spec(m, "kring:12,1"), select_k_ring(vertex_adjacency(m), 12, 1));
  EXPECT_EQ(select_by_spec(m, "nearest:2,2,0,3"), (std::vector<int>{7, 11, 12}));
  expect_input_error([&] { select_by_spec(m, "sphere:0,0,1"); }, "selection 'sphere:0,0,1'");
  expect_input_error([&] { select_by_spec(m, "kring:1.5,1"); }, "must be an integer");
  expect_input_error([&] { select_by_spec(m, "blob:1"); }, "expected all |");
  expect_input_error([&] { select_by_spec(m, "nearest:0,0,0,99"); }, "count 99");
}

TEST(Transform, ConstructorsAndSpecs) {
  EXPECT_EQ(apply(translation(Vec3(1, 2, 3)), Vec3(1, 1, 1)), Vec3(2, 3, 4));
  const Mat4 R = rotation_about_axis(Vec3(0, 0, 2), 90, Vec3(1, 0, 0));
  EXPECT_NEAR((apply(R, Vec3(2, 0, 0)) - Vec3(1, 1, 0)).norm(), 0, 1e-15);
  EXPECT_NEAR((apply(R, Vec3(1, 0, 5)) - Vec3(1, 0, 5)).norm(), 0, 1e-15);  // points on the axis stay
  expect_input_error([] { rotation_about_axis(Vec3::Zero(), 10); }, "non-zero");

  EXPECT_EQ(parse_transform("translate:1,-2,3.5"), translation(Vec3(1, -2, 3.5)));
  EXPECT_EQ(parse_transform("rotate:90:0,0,2:1,0,0"), R);
  EXPECT_EQ(parse_transform(" rotate:45:1,0,0 "), rotation_about_axis(Vec3(1, 0, 0), 45));
  const Mat4 M = parse_transform("matrix:1,0,0,4, 0,1,0,5, 0,0,1,6, 0,0,0,1");
  EXPECT_EQ(M, translation(Vec3(4, 5, 6)));
  for (const char* bad : {"translate:1,2", "translate:1,2,x", "rotate:abc:0,0,1", "rotate:90", "rotate:90:0,0,0",
                          "rotate:9:1,0,0:1,2", "matrix:1,2,3", "matrix:1,0,0,0,0,1,0,0,0,0,1,0,0,0,1,1", "shear:1",
                          "translate", "", "def:"})
    EXPECT_THROW(parse_transform(bad), InputError) << bad;
  expect_input_error([] { parse_transform("spin:3"); }, "transform 'spin:3'");
}

TEST_F(EditFiles, TransformFromDefFile) {
  write("t.def", "1 0 0 7\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  EXPECT_EQ(parse_transform("def:" + path("t.def")), translation(Vec3(7, 0, 0)));
  EXPECT_EQ(parse_transform("def:t.def", dir_.string()), translation(Vec3(7, 0, 0)));
  expect_input_error([&] { parse_transform("def:" + path("none.def")); }, "cannot open transform file");
}

TEST_F(EditFiles, LoadEditFileWithGeometricSelections) {
  write_mesh(path("tube.off"), make_cylinder(21, 8, 1.0, 10.0));
  write("ids.txt", "0 1 2\n");
  const std::string edit = write("bend.edit",
                                 "# a bend\nmesh = tube.off\nname = my bend\nroi = box:-2,-2,2,2,2,10\n"
                                 "handle = nearest:0,0,10,8\ntransform = rotate:30:1,0,0:0,0,5\n");
  const EditCase c = load_edit_case(edit);
  EXPECT_EQ(c.edit.name, "my bend");
  EXPECT_EQ(c.mesh_path, path("tube.off"));
  EXPECT_EQ(c.edit.count(Role::Handle), 8);
  for (int v : c.edit.vertices(Role::Handle)) EXPECT_EQ(c.mesh.V(v, 2), 10.0);
  for (int v : c.edit.vertices(Role::Fixed)) EXPECT_LT(c.mesh.V(v, 2), 2.0);
  EXPECT_EQ(c.edit.transform, rotation_about_axis(Vec3(1, 0, 0), 30, Vec3(0, 0, 5)));

  // indices: selections and a def file, relative to the .edit file; the default name is the file stem.
  write("h.def", "1 0 0 0\n0 1 0 0\n0 0 1 1\n0 0 0 1\n");
  const EditCase d = load_edit_case(write("lift.edit", "mesh = tube.off\nroi = kring:0,3\nhandle = indices:ids.txt\ndef = h.def\n"));
  EXPECT_EQ(d.edit.name, "lift");
  EXPECT_EQ(d.edit.vertices(Role::Handle), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(d.edit.transform, translation(Vec3(0, 0, 1)));
}

TEST_F(EditFiles, LoadEditFileErrorsNameTheFile) {
  write_mesh(path("tube.off"), make_cylinder(11, 6, 1.0, 10.0));
  const std::string ok = "mesh = tube.off\nroi = all\nhandle = nearest:0,0,10,3\n";
  expect_input_error([&] { load_edit_case(write("a.edit", ok + "transform = translate:0,0,1\ncolour = red\n")); },
                     "a.edit: line 5: unknown key 'colour'");
  expect_input_error([&] { load_edit_case(write("b.edit", "roi = all\nhandle = all\ntransform = translate:0,0,1\n")); },
                     "b.edit: missing 'mesh");
  expect_input_error([&] { load_edit_case(write("c.edit", ok)); }, "c.edit: give exactly one of 'def");
  expect_input_error([&] { load_edit_case(write("d.edit", ok + "transform = wobble\n")); }, "d.edit: line 4");
  expect_input_error(
      [&] { load_edit_case(write("e.edit", "mesh = tube.off\nroi = box:-9,-9,0,9,9,1\nhandle = nearest:0,0,10,3\n"
                                           "transform = translate:0,0,1\n")); },
      "is outside the region of interest");
  expect_input_error([&] { load_edit_case(write("f.edit", "mesh = none.off\nroi = all\nhandle = all\ntransform = translate:0,0,1\n")); },
                     "f.edit: line 1: cannot open mesh file");
  expect_input_error([&] { load_edit_case(write("g.edit", ok + "transform = translate:0,0,1\nsel = x.sel\n")); },
                     "g.edit: give either 'sel'");
  expect_input_error([&] { load_edit_case(write("h.edit", ok + "transform = translate:0,0,1\nroi = all\n")); },
                     "h.edit: line 5: 'roi' given twice");
  expect_input_error([&] { load_edit_case(write("i.edit", "mesh tube.off\n")); }, "i.edit: line 1: expected 'key = value'");
  expect_input_error([&] { load_edit_case(write("j.edit", "mesh = tube.off\nroi = sphere:0,0,0,0.1\nhandle = sphere:0,0,99,0.1\n"
                                                         "transform = translate:0,0,1\n")); },
                     "selects no vertex");
  expect_input_error([&] { load_edit_case(write("k.edit", "mesh = tube.off\nroi = all\nhandle = all\ntransform = translate:0,0,1\n")); },
                     "no free vertex");
  expect_input_error([&] { load_edit_case(path("missing.edit")); }, "cannot open edit file");
  expect_input_error([&] { load_edit_case(path("nostem")); }, path("nostem") + ".off is missing");
  write_mesh(path("half.off"), make_cylinder(3, 4, 1, 1));
  expect_input_error([&] { load_edit_case(path("half")); }, path("half") + ".sel is missing");
  std::filesystem::create_directory(path("dirstem.off"));  // there, but no file
  expect_input_error([&] { load_edit_case(path("dirstem")); }, path("dirstem") + ".off is not a regular file");
}

TEST(CgalCactus, StemAndEditFileAgree) {
  const std::string stem = DEFORMBENCH_SOURCE_DIR "/data/meshes/cactus_cgal";
  ASSERT_TRUE(fs::exists(stem + ".sel")) << stem << ".sel is missing: run scripts/data.sh (./run test does)";
  const EditCase a = load_edit_case(stem);
  const EditCase b = load_edit_case(DEFORMBENCH_SOURCE_DIR "/data/edits/cactus_cgal.edit");
  EXPECT_EQ(a.edit.roles, b.edit.roles);
  EXPECT_EQ(a.edit.transform, b.edit.transform);
  EXPECT_EQ(a.edit.name, "cactus_cgal");
  EXPECT_EQ(b.edit.name, "cactus_cgal");
  EXPECT_GT(a.edit.count(Role::Handle), 0);
}

}  // namespace
