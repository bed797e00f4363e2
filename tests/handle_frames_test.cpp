// Handle-mode frames (issue 16, systems/handle_response.h) against full-mode frames: the same positions for every
// method, constraint mode, build and a few backends, to 1e-10 of the bounding-box diagonal. The BS08 edits and the
// 104k tier are checked by scripts/handle_frames.sh, which records the differences (results/handle_frames.csv).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "edit/transform.h"
#include "methods/deformer.h"
#include "methods/drag.h"
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

// Largest difference between the two modes over the handle maps and a drag towards the first, / bbox diagonal.
double handle_vs_full(const Mesh& m, const Edit& e, DeformOptions o) {
  o.frame_mode = FrameMode::Full;
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
    const Points a = full->deform(T), b = handle->deform(T);
    EXPECT_GT(handle->times().response, 0.0);
    worst = std::max(worst, rel_max(b, a));
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
    o.method = c.method;
    o.build = parse_build(c.build);
    o.solver = c.solver;
    o.constraints = mode;
    o.soft_weight = mode == ConstraintMode::Soft ? 3.0 : 1.0;
    EXPECT_LT(handle_vs_full(m, e, o), 1e-10) << to_string(mode);
    if (c.method == "lri") {
      o.lri_orthonormalize = "polar";
      EXPECT_LT(handle_vs_full(m, e, o), 1e-10) << to_string(mode) << " polar";
      continue;
    }
    o.weights = Weights::Cotan;
    o.tf_translation = false;
    EXPECT_LT(handle_vs_full(m, e, o), 1e-10) << to_string(mode) << " cotan, no translation";
  }
}

INSTANTIATE_TEST_SUITE_P(
    Methods, HandleFrames,
    ::testing::Values(Case{"lap", "structured", ""}, Case{"lap", "naive", ""}, Case{"lap", "dense", ""},
                      Case{"tf", "structured", ""}, Case{"tf", "naive", ""}, Case{"tf", "dense", ""},
                      Case{"tf", "structured", "cholmod_supernodal"}, Case{"lap", "structured", "eigen_simplicial_ldlt"},
                      Case{"lri", "structured", ""}, Case{"lri", "naive", ""},
                      Case{"lri", "structured", "cholmod_supernodal"}),
    [](const auto& info) { return info.param.method + "_" + info.param.build + "_" +
                                  (info.param.solver.empty() ? std::string("default") : info.param.solver); });

TEST(HandleFrames, ThreadedStreamEqualsFullFrames) {
  // 14400 vertices of TF: 4.5 MB of responses, streamed on two threads.
  const Mesh m = make_cylinder(120, 120, 1.0, 4.0);
  const Edit e = tube_edit(m);
  DeformOptions o;
  o.method = "tf";
  o.constraints = ConstraintMode::Soft;
  EXPECT_LT(handle_vs_full(m, e, o), 1e-10);
}

TEST(HandleFrames, ParsesFrameModes) {
  EXPECT_EQ(parse_frame_mode("full"), FrameMode::Full);
  EXPECT_EQ(parse_frame_mode("handle"), FrameMode::Handle);
  EXPECT_EQ(to_string(FrameMode::Handle), "handle");
  expect_input_error([] { parse_frame_mode("fast"); }, "unknown frame mode 'fast'");
}

}  // namespace
}  // namespace db
