#pragma once
// Helpers the gtest suites share: the test tube and its edit, a per-test temporary directory, the BS08 data,
// bad-input expectations and distances between results.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "solvers/base/error.h"
#include "edit/edit.h"
#include "mesh/mesh.h"
#include "mesh/procedural.h"
#include "methods/quality_metrics.h"

namespace db {

//! The test tube: 12 rings of 16 vertices, radius 1, from z = 0 to z = 4.
inline Mesh tube() { return make_cylinder(12, 16, 1.0, 4.0); }

//! Bottom ring(s) fixed, top ring(s) handle (within 0.5 of either end), the rest free; `all_handle` turns the
//! fixed part into handle too.
inline Edit tube_edit(const Mesh& m, bool all_handle = false) {
  Edit e;
  e.name = "tube";
  e.roles.assign(m.num_vertices(), Role::Free);
  const double zmax = m.V.col(2).maxCoeff(), zmin = m.V.col(2).minCoeff();
  for (int v = 0; v < m.num_vertices(); ++v) {
    const double z = m.V(v, 2);
    if (z < zmin + 0.5) e.roles[v] = all_handle ? Role::Handle : Role::Fixed;
    if (z > zmax - 0.5) e.roles[v] = Role::Handle;
  }
  return e;
}

//! Every point of V moved by T.
inline Points transformed(const Points& V, const Mat4& T) {
  Points out(V.rows(), 3);
  for (int i = 0; i < V.rows(); ++i) out.row(i) = apply(T, V.row(i).transpose()).transpose();
  return out;
}

//! RMS and largest distance between corresponding points of a and b, over b's bounding-box diagonal.
inline double rel_rms(const Points& a, const Points& b) { return distance_between(a, b, bbox_diagonal(b)).rms; }
inline double rel_max(const Points& a, const Points& b) { return distance_between(a, b, bbox_diagonal(b)).max; }

//! The Botsch-Sorkine 2008 survey edits bundled with the sources (data/bs08/STEM.{off,sel,def}).
inline std::filesystem::path bs08_dir() { return std::filesystem::path(DEFORMBENCH_SOURCE_DIR) / "data" / "bs08"; }
inline const std::vector<std::string> kBs08Cases = {"plane", "cylinder", "bar", "cactus"};

//! f() must throw InputError with `substr` in its message.
template <class F>
void expect_input_error(F&& f, const std::string& substr) {
  try {
    f();
    ADD_FAILURE() << "expected InputError containing '" << substr << "'";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(substr), std::string::npos) << "message: " << e.what();
  }
}

//! A fixture with a fresh temporary directory per test, removed afterwards.
class TempDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() / ("deformbench_" + std::string(info->test_suite_name()) + "_" +
                                                     std::to_string(::getpid()) + "_" + info->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  //! Writes `content` as is (binary) to path(name) and returns that path.
  std::string write(const std::string& name, const std::string& content) const {
    std::ofstream(path(name), std::ios::binary) << content;
    return path(name);
  }
  std::filesystem::path dir_;
};

}  // namespace db
