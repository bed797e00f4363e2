// Handle-mode frames (issue 16, systems/handle_response.h) and full-mode frames: the same positions for every
// method, constraint mode, build and a few backends, both the exact deformation up to the rounding the systems'
// conditioning allows (exact_deformation.h). The BS08 edits and the 104k tier are checked by
// experiments/handle_frames.py, which records the differences (its handle_frames.csv).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "edit/edit_io.h"
#include "edit/transform.h"
#include "mesh/mesh_io.h"
#include "methods/deformer.h"
#include "methods/drag.h"
#include "exact_deformation.h"
#include "test_util.h"

namespace db {
namespace {

// A general affine handle map (rotation, non-uniform scale, shear, translation) and a rigid one.
std::vector<Mat4> handle_maps() {
  Mat4 A = rotation_about_axis(Vec3(1, 0.3, 0.2).normalized(), 35.0, Vec3(0, 0, 2));
  Mat4 S = Mat4::Identity();
  S(0, 0) = 1.2;
  S(1, 2) = 0.15;
  S(2, 2) = 0.9;
  A = translation(Vec3(0.2, -0.4, 0.7)) * A * S;
  return {A, rotation_about_axis(Vec3(0, 1, 0), 60.0, Vec3(0, 0, 4)), Mat4::Identity()};
}

// Largest error (normalized_rel) of either mode over the handle maps and a drag towards the first, against the exact
// deformation (exact_deformation.h); the tests hold it to deformation_bound(), the systems' conditioning's: the two
// modes round differently (a frame of handle mode sums stored responses), so they are not compared with each other.
double handle_and_full_error(const Mesh& m, const Edit& e, DeformOptions o) {
  o.frame_mode = FrameMode::Full;
  auto exact = make_deformer(m, e, exact_options(o));
  auto full = make_deformer(m, e, o);
  o.frame_mode = FrameMode::Handle;
  auto handle = make_deformer(m, e, o);
  EXPECT_EQ(handle->frame_mode(), FrameMode::Handle);
  EXPECT_GT(handle->response_bytes(), 0u);
  EXPECT_GT(handle->times().precompute, 0.0);
  EXPECT_EQ(full->times().precompute, 0.0);
  std::vector<Mat4> maps = handle_maps();
  for (double f : {0.25, 0.5}) maps.push_back(interpolate_transform(maps.front(), f));
  double worst = 0;
  for (const Mat4& T : maps) {
    const Points ref = exact->deform(T), a = full->deform(T), b = handle->deform(T);
    EXPECT_GT(handle->times().response, 0.0);
    worst = std::max({worst, normalized_rel(m, a, ref), normalized_rel(m, b, ref)});
  }
  return worst;
}

struct Case {
  std::string method, build, solver;
};

class HandleFrames : public ::testing::TestWithParam<Case> {};

TEST_P(HandleFrames, EqualFullFramesOnTheTube) {
  const Case c = GetParam();
  const Mesh m = tube();
  const Edit e = tube_edit(m);
  for (auto mode : {ConstraintMode::Hard, ConstraintMode::Soft}) {
    DeformOptions o;
    o.method = parse_enum<Method>(c.method);
    o.build = parse_enum<Build>(c.build);
    o.solver = c.solver;
    o.constraints = mode;
    o.soft_weight = mode == ConstraintMode::Soft ? 3.0 : 1.0;
    EXPECT_WITHIN(handle_and_full_error(m, e, o), deformation_bound(m, e, o)) << to_string(mode);
    if (c.method == "lri") {
      o.lri_orthonormalize = Orthonormalization::Polar;
      EXPECT_WITHIN(handle_and_full_error(m, e, o), deformation_bound(m, e, o)) << to_string(mode) << " polar";
      continue;
    }
    o.weights = Weights::Cotan;
    o.tf_translation = false;
    EXPECT_WITHIN(handle_and_full_error(m, e, o), deformation_bound(m, e, o))
        << to_string(mode) << " cotan, no translation";
  }
}

INSTANTIATE_TEST_SUITE_P(
    Methods, HandleFrames,
    ::testing::Values(Case{"lap", "structured", ""}, Case{"lap", "naive", ""}, Case{"lap", "dense", ""},
                      Case{"tf", "structured", ""}, Case{"tf", "naive", ""}, Case{"tf", "dense", ""},
                      Case{"tf", "structured", "cholmod_supernodal"}, Case{"lap", "structured", "eigen_simplicial_ldlt"},
                      Case{"lri", "structured", ""}, Case{"lri", "naive", ""},
                      Case{"lri", "structured", "cholmod_supernodal"}, Case{"lap", "structured", "multifrontal_refined"},
                      Case{"tf", "structured", "multifrontal_refined"}, Case{"lri", "structured", "multifrontal_refined"}),
    [](const auto& info) { return info.param.method + "_" + info.param.build + "_" +
                                  (info.param.solver.empty() ? std::string("default") : info.param.solver); });

TEST(HandleFrames, ThreadedStreamEqualsFullFrames) {
  // 14400 vertices of TF: 4.5 MB of responses, streamed on two threads.
  const Mesh m = make_cylinder(120, 120, 1.0, 4.0);
  const Edit e = tube_edit(m);
  DeformOptions o;
  o.method = Method::Tf;
  o.constraints = ConstraintMode::Soft;
  EXPECT_WITHIN(handle_and_full_error(m, e, o), deformation_bound(m, e, o));
}

// A general drag of the edit's handle: frame f moves each handle vertex by its own, non-affine displacement.
Points drag_targets(const Mesh& m, const Edit& e, int frames) {
  const std::vector<int> h = e.vertices(Role::Handle);
  Points t(static_cast<Eigen::Index>(frames * h.size()), 3);
  for (int f = 0; f < frames; ++f)
    for (std::size_t k = 0; k < h.size(); ++k) {
      const Vec3 p = m.V.row(h[k]).transpose();
      const double s = (f + 1.0) / frames;
      const Vec3 d(0.3 * std::sin(3 * p.y()), 0.2 * p.x() * p.x(), 0.4 * std::cos(p.x() + p.z()));
      t.row(static_cast<Eigen::Index>(f * h.size() + k)) = (p + s * d).transpose();
    }
  return t;
}

// The tube's edit with `frames` frames of drag_targets.
Edit tube_drag(const Mesh& m, int frames) {
  Edit e = tube_edit(m);
  e.targets = drag_targets(m, e, frames);
  return e;
}

// Largest error of full and handle frames over every frame of the edit's targets against the exact deformation
// (as handle_and_full_error).
double drag_handle_and_full_error(const Mesh& m, const Edit& e, DeformOptions o) {
  o.frame_mode = FrameMode::Full;
  auto exact = make_deformer(m, e, exact_options(o));
  auto full = make_deformer(m, e, o);
  o.frame_mode = FrameMode::Handle;
  o.handle_limit = 1e6;  // small meshes: the responses outgrow the factor, which these tests do not mind
  auto handle = make_deformer(m, e, o);
  EXPECT_EQ(handle->frame_mode(), FrameMode::Handle);
  EXPECT_TRUE(handle->frame_mode_note().empty());
  const Eigen::Index h = e.count(Role::Handle);
  // TF: 3h responses and the rest column per coordinate row; LAP: h and 3 rest columns per vertex row.
  const std::size_t per_row = o.method == Method::Tf ? 3 * (3 * h + 1) : h + 3;
  EXPECT_EQ(handle->response_bytes(), per_row * static_cast<std::size_t>(m.num_vertices()) * sizeof(double));
  double worst = 0;
  for (int f = 0; f < e.target_frames(); ++f) {
    const Points t = e.targets.middleRows(f * h, h);
    const Points ref = exact->deform_targets(t), a = full->deform_targets(t), b = handle->deform_targets(t);
    worst = std::max({worst, normalized_rel(m, a, ref), normalized_rel(m, b, ref)});
  }
  return worst;
}

TEST(HandleFrames, PerVertexDragsEqualFullFrames) {
  const Mesh m = tube();
  const Edit e = tube_drag(m, 3);
  for (const char* method : {"lap", "tf"})
    for (auto mode : {ConstraintMode::Hard, ConstraintMode::Soft}) {
      DeformOptions o;
      o.method = parse_enum<Method>(method);
      o.constraints = mode;
      o.soft_weight = mode == ConstraintMode::Soft ? 3.0 : 1.0;
      EXPECT_WITHIN(drag_handle_and_full_error(m, e, o), deformation_bound(m, e, o))
          << method << " " << to_string(mode);
      o.weights = Weights::Cotan;
      EXPECT_WITHIN(drag_handle_and_full_error(m, e, o), deformation_bound(m, e, o))
          << method << " " << to_string(mode) << " cotan";
    }
}

TEST(HandleFrames, ThreadedPerVertexDragEqualsFullFrames) {
  // 14400 vertices, 8 handle vertices of the top ring, TF: 8.6 MB of responses, streamed on the worker threads.
  const Mesh m = make_cylinder(120, 120, 1.0, 4.0);
  Edit e = tube_edit(m);
  int kept = 0;
  for (int v = 0; v < m.num_vertices(); ++v)
    if (e.roles[v] == Role::Handle && (m.V(v, 2) < 3.99 || ++kept > 8)) e.roles[v] = Role::Free;
  e.targets = drag_targets(m, e, 2);
  DeformOptions o;
  o.method = Method::Tf;
  o.constraints = ConstraintMode::Soft;
  EXPECT_WITHIN(drag_handle_and_full_error(m, e, o), deformation_bound(m, e, o));
}

TEST(HandleFrames, RigidPerVertexDragEqualsTheAffinePath) {
  const Mesh m = tube();
  Edit e = tube_edit(m);
  const Mat4 T = translation(Vec3(0.3, -0.2, 0.5)) * rotation_about_axis(Vec3(1, 0.3, 0.2).normalized(), 40.0,
                                                                          Vec3(0, 0, 4));
  Points t(e.count(Role::Handle), 3);
  const std::vector<int> h = e.vertices(Role::Handle);
  for (std::size_t k = 0; k < h.size(); ++k) t.row(static_cast<Eigen::Index>(k)) = apply(T, m.V.row(h[k]).transpose()).transpose();
  Edit drag = e;
  drag.targets = t;
  for (const char* method : {"lap", "tf"})
    for (auto mode : {ConstraintMode::Hard, ConstraintMode::Soft}) {
      DeformOptions o;
      o.method = parse_enum<Method>(method);
      o.constraints = mode;
      // Each path against the exact deformation under the system's bound (they round differently).
      const Points ref = make_deformer(m, e, exact_options(o))->deform(T);
      const double tol = deformation_bound(m, e, o);
      o.frame_mode = FrameMode::Handle;
      EXPECT_WITHIN(normalized_rel(m, make_deformer(m, e, o)->deform(T), ref), tol) << method << " affine";
      EXPECT_WITHIN(normalized_rel(m, make_deformer(m, drag, o)->deform_targets(t), ref), tol) << method << " handle";
      o.frame_mode = FrameMode::Full;
      EXPECT_WITHIN(normalized_rel(m, make_deformer(m, drag, o)->deform_targets(t), ref), tol) << method << " full";
    }
}

TEST(HandleFrames, LargeDragsFallBackToFullFrames) {
  const Mesh m = tube();
  const Edit e = tube_drag(m, 1);
  DeformOptions o;
  o.method = Method::Tf;
  o.frame_mode = FrameMode::Handle;
  o.handle_limit = 1e-3;  // the tube's 32 handle vertices: responses far above a thousandth of the factor
  auto d = make_deformer(m, e, o);
  EXPECT_EQ(d->frame_mode(), FrameMode::Full);
  EXPECT_NE(d->frame_mode_note().find("above the handle limit 0.001"), std::string::npos) << d->frame_mode_note();
  EXPECT_EQ(d->response_bytes(), 0u);
  o.frame_mode = FrameMode::Full;
  const Points ref = make_deformer(m, e, exact_options(o))->deform_targets(e.targets);
  EXPECT_WITHIN(normalized_rel(m, d->deform_targets(e.targets), ref), deformation_bound(m, e, o));
}

TEST(HandleFrames, LriRefusesPerVertexTargets) {
  const Mesh m = tube();
  const Edit e = tube_drag(m, 1);
  DeformOptions o;
  o.method = Method::Lri;
  expect_input_error([&] { make_deformer(m, e, o); }, "need --method lap or tf");
  o.method = Method::Tf;
  expect_input_error([&] { make_deformer(m, e, o)->deform_targets(e.targets.topRows(3)); }, "expected 32 finite");
}

class DragFiles : public TempDirTest {
 protected:
  // A .edit of the tube with `targets = NAME` holding `content`; the handle is the top two rings (32 vertices).
  std::string edit_with(const std::string& content, const std::string& extra = "") {
    write_mesh(path("tube.off"), tube());
    write("t.txt", content);
    return write("drag.edit", "mesh = tube.off\nroi = all\nhandle = box:-2,-2,3.5,2,2,5\ntargets = t.txt\n" + extra);
  }
  static std::string lines(int n, const std::string& line) {
    std::string s;
    for (int i = 0; i < n; ++i) s += line + "\n";
    return s;
  }
};

TEST_F(DragFiles, ReadsFramesOfTargets) {
  const EditCase c = load_edit_case(edit_with("# two frames\n" + lines(64, "0.5, 1 2.5")));
  EXPECT_EQ(c.edit.count(Role::Handle), 32);
  EXPECT_EQ(c.edit.target_frames(), 2);
  EXPECT_EQ(c.edit.targets(63, 2), 2.5);
  const auto files = edit_case_files(path("drag.edit"));
  EXPECT_NE(std::find(files.begin(), files.end(), path("t.txt")), files.end());
}

TEST_F(DragFiles, RefusesBadTargets) {
  expect_input_error([&] { load_edit_case(edit_with(lines(33, "0 0 0"))); },
                     "33 target positions are not a whole number of frames of the handle's 32 vertices");
  expect_input_error([&] { load_edit_case(edit_with(lines(31, "0 0 0") + "0 nan 0\n")); }, "line 32: bad number 'nan'");
  expect_input_error([&] { load_edit_case(edit_with(lines(31, "0 0 0") + "0 1e999 0\n")); }, "bad number '1e999'");
  expect_input_error([&] { load_edit_case(edit_with("1 2\n")); }, "line 1: expected 3 numbers (x y z), got 2");
  expect_input_error([&] { load_edit_case(edit_with("# nothing\n")); }, "no target positions");
  expect_input_error([&] { load_edit_case(edit_with(lines(32, "0 0 0"), "transform = translate:0,0,1\n")); },
                     "exactly one of 'def = FILE', 'transform = SPEC' and 'targets = FILE'");
}

TEST(HandleFrames, ParsesFrameModes) {
  EXPECT_EQ(parse_enum<FrameMode>("full"), FrameMode::Full);
  EXPECT_EQ(parse_enum<FrameMode>("handle"), FrameMode::Handle);
  EXPECT_EQ(to_string(FrameMode::Handle), "handle");
  expect_input_error([] { parse_enum<FrameMode>("fast"); }, "unknown frame mode 'fast'");
}

}  // namespace
}  // namespace db
