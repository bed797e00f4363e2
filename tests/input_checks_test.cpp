// Deformation-level input checks: each selection mistake named by its cause, the input files an edit case reads
// (for refusing an output that would overwrite one), and scale independence (a mesh scaled by 1e200 or 1e-300
// deforms like the unscaled one, or is refused naming the coordinate that doubles cannot hold).
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "core/input_file.h"
#include "edit/edit_io.h"
#include "edit/selection.h"
#include "edit/transform.h"
#include "mesh/mesh_io.h"
#include "mesh/procedural.h"
#include "methods/deformer.h"
#include "methods/normalization.h"
#include "exact_deformation.h"

namespace db {
namespace {

namespace fs = std::filesystem;

// The InputError message `f` throws ("" and a failure when it throws none).
template <class F>
std::string input_error(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an InputError";
  return {};
}

#define EXPECT_MENTIONS(msg, text) EXPECT_NE((msg).find(text), std::string::npos) << "message: " << (msg)

// A tube around the z axis, z in [0, 4], radius 1, 12 rings of 16 vertices.
Mesh tube() { return make_cylinder(12, 16, 1.0, 4.0); }

TEST(SelectionErrors, EachMistakeNamesItsCause) {
  const Mesh m = tube();
  const int nv = m.num_vertices();
  EXPECT_MENTIONS(input_error([&] { select_by_spec(m, "sphere:0,0,0,-1"); }), "the radius -1 is negative");
  EXPECT_MENTIONS(input_error([&] { select_by_spec(m, "box:1,-1,0,-1,1,4"); }), "box: inverted in x (1 > -1)");
  EXPECT_MENTIONS(input_error([&] { select_by_spec(m, "box:-1,-1,4,1,1,0"); }), "inverted in z (4 > 0)");
  EXPECT_MENTIONS(input_error([&] { select_by_spec(m, "kring:9999,1"); }), "seed vertex 9999 out of range");
  EXPECT_MENTIONS(input_error([&] { select_by_spec(m, "kring:-1,1"); }), "seed vertex -1 out of range");
  EXPECT_MENTIONS(input_error([&] { select_by_spec(m, "kring:0,-2"); }), "k must be >= 0 (got -2)");
  EXPECT_MENTIONS(input_error([&] { select_by_spec(m, "nearest:0,0,0,0"); }),
                  fmt::format("count 0 must be in [1, {}]", nv));
  EXPECT_MENTIONS(input_error([&] { select_by_spec(m, fmt::format("nearest:0,0,0,{}", nv + 1)); }),
                  fmt::format("count {} must be in [1, {}]", nv + 1, nv));
  // Each message names the spec it came from.
  EXPECT_MENTIONS(input_error([&] { select_by_spec(m, "sphere:0,0,0,-1"); }), "selection 'sphere:0,0,0,-1'");
  // A zero radius or a flat box is no mistake.
  EXPECT_NO_THROW(select_by_spec(m, "sphere:1,0,0,0"));
  EXPECT_NO_THROW(select_by_spec(m, "box:-1,-1,0,1,1,0"));
}

class EditDir : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("input_checks_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    write_mesh(path("tube.off"), tube());
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  // An .edit file on tube.off with the given roi and handle selections.
  std::string edit(const std::string& name, const std::string& roi, const std::string& handle) const {
    std::ofstream(path(name)) << "mesh = tube.off\nroi = " << roi << "\nhandle = " << handle
                              << "\ntransform = translate:0,0,1\n";
    return path(name);
  }
  fs::path dir_;
};

using EditErrors = EditDir;

TEST_F(EditErrors, EmptyRoiAndHandleAreNamedNotReportedAsOutsideTheRoi) {
  const std::string top = "box:-2,-2,3.9,2,2,4";
  std::string msg = input_error([&] { load_edit_case(edit("far.edit", "sphere:50,50,50,1", top)); });
  EXPECT_MENTIONS(msg, "far.edit: line 2: roi selection 'sphere:50,50,50,1' selects no vertex");
  EXPECT_MENTIONS(msg, "the mesh spans (-1, -1, 0) to (1, 1, 4)");
  msg = input_error([&] { load_edit_case(edit("h.edit", "all", "box:5,5,5,6,6,6")); });
  EXPECT_MENTIONS(msg, "line 3: handle selection 'box:5,5,5,6,6,6' selects no vertex");
  msg = input_error([&] { load_edit_case(edit("inv.edit", "box:2,2,4,-2,-2,0", top)); });
  EXPECT_MENTIONS(msg, "inv.edit: line 2");
  EXPECT_MENTIONS(msg, "inverted in x");
  EXPECT_MENTIONS(input_error([&] { load_edit_case(edit("neg.edit", "sphere:0,0,2,-3", top)); }), "negative");
  EXPECT_MENTIONS(input_error([&] { load_edit_case(edit("k.edit", "kring:100000,2", top)); }), "out of range");
  // A real handle outside the roi keeps its own message, with the count.
  msg = input_error([&] { load_edit_case(edit("out.edit", "box:-2,-2,0,2,2,2", top)); });
  EXPECT_MENTIONS(msg, "is outside the region of interest (16 of the 16 handle vertices are)");
  EXPECT_MENTIONS(input_error([] { edit_from_lists(5, {}, {1}, Mat4::Identity()); }),
                  "the region of interest is empty");
}

using EditFiles = EditDir;

TEST_F(EditFiles, ListsWhatAnEditCaseReads) {
  std::ofstream(path("ids.txt")) << "1 2\n";
  std::ofstream(path("a.edit")) << "mesh = tube.off\nroi = all\nhandle = indices:ids.txt\ntransform = def:sub/t.def\n";
  EXPECT_EQ(edit_case_files(path("a.edit")),
            (std::vector<std::string>{path("a.edit"), path("tube.off"), path("ids.txt"), path("sub/t.def")}));
  std::ofstream(path("b.edit")) << "mesh = /abs/m.ply\nsel = b.sel\ndef = b.def\n";
  EXPECT_EQ(edit_case_files(path("b.edit")),
            (std::vector<std::string>{path("b.edit"), "/abs/m.ply", path("b.sel"), path("b.def")}));
  // A stem: its mesh as load_edit_case would pick it (STEM.off when there is none yet).
  const std::vector<std::string> stem = {path("tube.off"), path("tube.sel"), path("tube.def")};
  EXPECT_EQ(edit_case_files(path("tube")), stem);
  EXPECT_EQ(edit_case_files(path("tube.sel")), stem);
  write_mesh(path("p.ply"), tube());
  EXPECT_EQ(edit_case_files(path("p")), (std::vector<std::string>{path("p.ply"), path("p.sel"), path("p.def")}));
  EXPECT_MENTIONS(input_error([&] { edit_case_files(path("missing.edit")); }), "cannot open edit file");
}

// Issue 28: every reader opens through InputFile. A FIFO without a writer is refused at once (a blocking open would
// hang here), a file larger than what it can sensibly hold before a byte is read, a line without end after a
// bounded read, and a targets file's frames are capped as --frames is.
TEST_F(EditFiles, SpecialAndOversizedInputsAreRefusedBeforeReading) {
  ASSERT_EQ(::mkfifo(path("fifo").c_str(), 0600), 0);
  ASSERT_EQ(::mkfifo(path("fifo.off").c_str(), 0600), 0);
  EXPECT_MENTIONS(input_error([&] { read_def(path("fifo")); }), "cannot open transform file: " + path("fifo") +
                                                                    " (not a regular file");
  EXPECT_MENTIONS(input_error([&] { read_targets(path("fifo")); }), "not a regular file");
  EXPECT_MENTIONS(input_error([&] { read_index_list(path("fifo")); }), "not a regular file");
  EXPECT_MENTIONS(input_error([&] { read_sel(path("fifo"), 3); }), "not a regular file");
  EXPECT_MENTIONS(input_error([&] { read_mesh(path("fifo.off")); }), "not a regular file");
  EXPECT_MENTIONS(input_error([&] { InputFile(path("."), "test"); }), "is a directory");

  std::ofstream(path("big.def")).close();
  fs::resize_file(path("big.def"), std::uintmax_t(1) << 31);  // sparse: no disk used
  EXPECT_MENTIONS(input_error([&] { read_def(path("big.def")); }), "holds 2147483648 bytes, more than");
  // A selection of a 3-vertex mesh, or an index list of it, holds a few lines, not 2 GB.
  EXPECT_MENTIONS(input_error([&] { read_sel(path("big.def"), 3); }), "holds 2147483648 bytes");
  EXPECT_MENTIONS(input_error([&] { read_index_list(path("big.def"), 3); }), "holds 2147483648 bytes");
  // Streamed readers stop at the first NUL byte, and at the first line that does not end.
  EXPECT_MENTIONS(input_error([&] { read_targets(path("big.def")); }), "line 1: holds a NUL byte");
  std::ofstream(path("long.txt")) << "0 0 1\n" << std::string(1 << 17, '7');
  EXPECT_MENTIONS(input_error([&] { read_targets(path("long.txt")); }), "line 2: longer than 65536 bytes");
  std::ofstream(path("big.off")).close();
  fs::resize_file(path("big.off"), std::uintmax_t(1) << 31);
  EXPECT_MENTIONS(input_error([&] { read_mesh(path("big.off")); }), "line 1: longer than 65536 bytes");
  InputFile f(path("big.def"), "test");
  EXPECT_EQ(f.size(), std::uint64_t(1) << 31);
  EXPECT_THROW(InputFile(path("big.def"), "test", 1000), InputError);

  std::ofstream(path("t.txt")) << "0 0 1\n# a comment\n0 0 2\n0 0 3\n";
  EXPECT_EQ(read_targets(path("t.txt"), 3).rows(), 3);
  EXPECT_MENTIONS(input_error([&] { read_targets(path("t.txt"), 2); }),
                  "t.txt: line 4: more than 2 target positions (" + std::to_string(kMaxFrames) + " frames");
  EXPECT_EQ(input_bytes({path("t.txt"), path("missing"), path("fifo")}), fs::file_size(path("t.txt")));
}

// ---- scale independence

Mesh scaled(Mesh m, double k) {
  m.V *= k;
  return m;
}

// The same affine map in coordinates scaled by k: its translation scales with them.
Mat4 scaled(Mat4 T, double k) {
  T.topRightCorner<3, 1>() *= k;
  return T;
}

// Bottom rings fixed, top rings the handle; the tube is moved off the origin so that centering matters.
struct Case {
  Mesh mesh;
  Edit edit;
};
Case bend() {
  Case c{tube(), {}};
  c.mesh.V.rowwise() += Eigen::RowVector3d(3, -2, 5);
  c.edit.name = "bend";
  c.edit.roles.assign(c.mesh.num_vertices(), Role::Free);
  for (int v = 0; v < c.mesh.num_vertices(); ++v) {
    const double z = c.mesh.V(v, 2) - 5;
    if (z < 0.5) c.edit.roles[v] = Role::Fixed;
    if (z > 3.5) c.edit.roles[v] = Role::Handle;
  }
  c.edit.transform = rotation_about_axis(Vec3(1, 0, 0), 40, Vec3(3, -2, 9)) * translation(Vec3(0.3, 0, 0));
  return c;
}

DeformOptions method_options(const std::string& method) {
  DeformOptions o;
  o.method = parse_enum<Method>(method);
  return o;
}

Points deform_once(const Case& c, const std::string& method) {
  return make_deformer(c.mesh, c.edit, method_options(method))->deform(c.edit.transform);
}

class ScaledMesh : public ::testing::TestWithParam<std::tuple<std::string, double>> {};

// The scaled mesh's result, scaled back, and the unscaled one: each against the exact deformation of the unscaled
// mesh (exact_deformation.h), under the bound of its systems' conditioning (scaling by k rounds the coordinates, a
// relative perturbation of eps, which that bound covers).
TEST_P(ScaledMesh, DeformsLikeTheUnscaledMesh) {
  const auto [method, k] = GetParam();
  const Case c = bend();
  const Points ref = deform_once(c, method);
  const Points exact = make_deformer(c.mesh, c.edit, exact_options(method_options(method)))->deform(c.edit.transform);
  const double tol = deformation_bound(c.mesh, c.edit, method_options(method));
  Case s = c;
  s.mesh = scaled(c.mesh, k);
  s.edit.transform = scaled(c.edit.transform, k);
  const Points out = deform_once(s, method);
  ASSERT_TRUE(out.allFinite());
  const double diag = bbox_diagonal(c.mesh.V);
  const double moved = (ref - c.mesh.V).rowwise().norm().maxCoeff() / diag;
  EXPECT_GT(moved, 0.1) << "the edit moves the tube";
  EXPECT_WITHIN(normalized_rel(c.mesh, ref, exact), tol) << method << " unscaled";
  EXPECT_WITHIN(normalized_rel(c.mesh, Points(out / k), exact), tol) << method << " at scale " << k;
}

INSTANTIATE_TEST_SUITE_P(LapTfLri, ScaledMesh,
                         ::testing::Combine(::testing::Values("lap", "tf", "lri"), ::testing::Values(1e200, 1e-300)));

TEST(ScaleLimits, UnrepresentableCoordinatesAreNamed) {
  const double big = std::numeric_limits<double>::max();
  Points V(3, 3);
  V << -0.9 * big, 0, 0, 0.9 * big, 0, 0, 0, 1, 0;  // x extent beyond the largest double
  std::string msg = input_error([&] { Normalization::fit(V); });
  EXPECT_MENTIONS(msg, "vertices 0 and 1 (their x coordinates -1.61792e+308 and 1.61792e+308)");
  EXPECT_MENTIONS(msg, "farther apart than a double can measure");

  V << 0.9 * big, 0, 0, 0, 0.9 * big, 0, 0, 0, 0.9 * big;  // each extent fits, the diagonal does not
  EXPECT_MENTIONS(input_error([&] { Normalization::fit(V); }), "the bounding-box diagonal overflows");

  V << 0, 0, 0, 1e-310, 0, 0, 0, 2e-310, 0;  // subnormal: the diagonal cannot be inverted
  msg = input_error([&] { Normalization::fit(V); });
  EXPECT_MENTIONS(msg, "below the smallest normal double");
  EXPECT_MENTIONS(msg, "vertices 0 and 2 (their y coordinates 0 and 2e-310)");

  // validate_mesh refuses such a mesh with the same message, not as degenerate faces.
  Mesh m;
  m.V = V * 1e300 * 1e10;  // the same triangle at unit size: fine
  m.F.resize(1, 3);
  m.F << 0, 1, 2;
  EXPECT_NO_THROW(validate_mesh(m));
  m.V << -0.9 * big, 0, 0, 0.9 * big, 0, 0, 0, 1e300, 0;
  EXPECT_MENTIONS(input_error([&] { validate_mesh(m); }), "farther apart than a double can measure");
}

TEST(ScaleLimits, ADeformationBeyondTheLargestDoubleIsNamed) {
  Case c = bend();
  const double k = 1e307;
  c.mesh = scaled(c.mesh, k);
  c.edit.transform = translation(Vec3(0, 0, 1.5e308));  // the handle lands beyond 1.8e308
  DeformOptions o;
  o.method = Method::Lap;
  const auto d = make_deformer(c.mesh, c.edit, o);
  const std::string msg = input_error([&] { d->deform(c.edit.transform); });
  EXPECT_MENTIONS(msg, "deformed vertex");
  EXPECT_MENTIONS(msg, "z coordinate");
}

}  // namespace
}  // namespace db
