// The experiment harness: budget decisions (a cell over budget is reported without being run), the child-process
// runner (measurements come back from a fresh process; a failing child is an error row, not a crash), the result
// line's encoding, the thesis edit and the power-law fit.
//
// This binary doubles as the cell child: run with "--cell ..." it measures one cell, as the drivers do.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "core/args.h"
#include "core/error.h"
#include "edit/edit.h"
#include "harness/budget.h"
#include "harness/cell.h"
#include "harness/stats.h"
#include "harness/subprocess.h"
#include "harness/thesis_edit.h"
#include "mesh/mesh_io.h"
#include "mesh/procedural.h"

namespace fs = std::filesystem;
using namespace db;
using namespace db::harness;

namespace {

// A closed box surface of 1178 vertices: big enough for 100 handle + 100 anchor vertices that do not overlap.
Mesh test_mesh() { return make_bar(8, 8, 24, 1.0, 1.0, 3.0); }

// The test mesh, written once per process into a private temporary directory removed at exit.
struct TempMesh {
  fs::path dir = fs::temp_directory_path() / ("db_harness_test_" + std::to_string(::getpid()));
  std::string path;
  TempMesh() {
    fs::create_directories(dir);
    path = (dir / "bar.off").string();
    write_mesh(path, test_mesh());
  }
  ~TempMesh() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};
std::string test_mesh_path() {
  static const TempMesh m;
  return m.path;
}

CellSpec spec_for(const std::string& system, const std::string& build) {
  CellSpec s;
  s.model = "bar";
  s.mesh_path = test_mesh_path();
  s.system = system;
  s.build = build;
  s.frames = 5;
  return s;
}

TEST(Budget, OverMemoryBudgetIsReportedWithoutRunning) {
  Prediction p;
  p.total_bytes = 5e9;
  p.seconds = 1;
  int calls = 0;
  const CellResult r = run_budgeted(spec_for("tf", "dense"), p, 1e9, 60, [&](const CellSpec&) {
    ++calls;
    return CellResult{};
  });
  EXPECT_EQ(calls, 0);
  EXPECT_EQ(r.status, "#over");
  EXPECT_DOUBLE_EQ(r.predicted.total_bytes, 5e9);
  EXPECT_NE(r.message.find("not attempted"), std::string::npos);
  EXPECT_TRUE(std::isnan(r.init_s));
}

TEST(Budget, OverTimeBudgetIsReportedWithoutRunning) {
  Prediction p;
  p.total_bytes = 1e6;
  p.seconds = 500;
  int calls = 0;
  const CellResult r = run_budgeted(spec_for("tf", "naive"), p, 1e9, 60, [&](const CellSpec&) {
    ++calls;
    return CellResult{};
  });
  EXPECT_EQ(calls, 0);
  EXPECT_EQ(r.status, "#slow");
  EXPECT_DOUBLE_EQ(r.predicted.seconds, 500);
}

TEST(Budget, WithinBudgetRunsTheCellAndKeepsThePrediction) {
  Prediction p;
  p.total_bytes = 1e6;
  p.seconds = 1;
  int calls = 0;
  const CellResult r = run_budgeted(spec_for("lap", "structured"), p, 1e9, 60, [&](const CellSpec&) {
    ++calls;
    CellResult c;
    c.init_s = 0.5;
    return c;
  });
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(r.status, "ok");
  EXPECT_DOUBLE_EQ(r.init_s, 0.5);
  EXPECT_DOUBLE_EQ(r.predicted.total_bytes, 1e6);
}

TEST(Budget, ZeroBudgetsAreUnlimited) {
  Prediction p;
  p.total_bytes = 1e15;
  p.seconds = 1e9;
  int calls = 0;
  run_budgeted(spec_for("lap", "dense"), p, 0, 0, [&](const CellSpec&) {
    ++calls;
    return CellResult{};
  });
  EXPECT_EQ(calls, 1);
}

TEST(Budget, PredictionsOrderTheBuildsAndMatchTheDenseSize) {
  const Mesh m = test_mesh();
  MachineRates rates;  // defaults: no measurement needed for the byte predictions
  CellPredictor pred(m, ThesisEditOptions{}, rates);
  for (const char* system : {"lap", "tf"}) {
    const double b = std::string(system) == "tf" ? 3 : 1, n = b * m.num_vertices();
    const Prediction d = pred.predict(spec_for(system, "dense")), nv = pred.predict(spec_for(system, "naive")),
                     st = pred.predict(spec_for(system, "structured"));
    EXPECT_DOUBLE_EQ(d.factor_bytes, n * n * 8) << system;
    EXPECT_GT(d.build_bytes, nv.build_bytes) << system;
    EXPECT_GT(nv.build_bytes, st.build_bytes) << system;
    EXPECT_GT(st.factor_bytes, 0) << system;
    EXPECT_GT(st.factor_flops, 0) << system;
    EXPECT_GT(st.seconds, 0) << system;
    EXPECT_GE(st.total_bytes, st.build_bytes + st.factor_bytes) << system;
  }
}

TEST(Budget, MeasuredRatesArePositive) {
  const MachineRates r = MachineRates::measure();
  EXPECT_GT(r.dense, 1e6);
  EXPECT_GT(r.sparse, 1e5);
  EXPECT_GT(r.stream, 1e6);
  const double gemm = MachineRates::blas_gemm();
  EXPECT_TRUE(std::isfinite(gemm));
  EXPECT_GT(gemm, 1e8);
  const double read = MachineRates::read_bandwidth();
  EXPECT_TRUE(std::isfinite(read));
  EXPECT_GT(read, 1e8);
}

TEST(ChildRunner, ReturnsTheChildsMeasurements) {
  CellSpec s = spec_for("tf", "structured");
  const CellResult r = run_cell_in_child(self_executable(), s, 120);
  ASSERT_EQ(r.status, "ok") << r.message;
  const double nv = test_mesh().num_vertices();
  EXPECT_EQ(r.vertices, nv);
  EXPECT_EQ(r.n, 3 * nv);  // soft constraints: every vertex is an unknown
  EXPECT_EQ(r.frames, 5);
  EXPECT_GT(r.init_s, 0);
  EXPECT_NEAR(r.init_s, r.build_s + r.analyze_s + r.factorize_s, 1e-9);
  EXPECT_GT(r.fps, 0);
  EXPECT_NEAR(r.fps * r.frame_s, 1.0, 1e-12);
  EXPECT_GT(r.factor_bytes, 0);
  EXPECT_FALSE(r.held_bytes.empty());
  EXPECT_GT(r.peak_rss_bytes, r.baseline_rss_bytes);
  EXPECT_GT(r.ru_maxrss_bytes, 0);
  EXPECT_GT(r.wall_s, 0);
  EXPECT_EQ(r.exit, "exit 0");
  EXPECT_GT(r.mean_displacement, 0);  // the handle moved the mesh
}

TEST(ChildRunner, BuildsAgreeOnTheDeformation) {
  const CellResult d = run_cell_in_child(self_executable(), spec_for("lap", "dense"), 120);
  const CellResult s = run_cell_in_child(self_executable(), spec_for("lap", "structured"), 120);
  ASSERT_EQ(d.status, "ok") << d.message;
  ASSERT_EQ(s.status, "ok") << s.message;
  EXPECT_NEAR(d.mean_displacement, s.mean_displacement, 1e-8);
}

// Out of core (the factor in a scratch file): the child passes --factor-dir on, the deformation is the same,
// and the prediction the budget is checked against leaves the factor's values out while still reporting them.
TEST(ChildRunner, OutOfCoreCellAgreesAndIsPredictedWithoutTheFactor) {
  CellSpec mem = spec_for("tf", "structured"), disk = mem;
  disk.factor_dir = fs::temp_directory_path().string();
  const CellResult a = run_cell_in_child(self_executable(), mem, 120);
  const CellResult b = run_cell_in_child(self_executable(), disk, 120);
  ASSERT_EQ(a.status, "ok") << a.message;
  ASSERT_EQ(b.status, "ok") << b.message;
  EXPECT_NEAR(a.mean_displacement, b.mean_displacement, 1e-12);
  EXPECT_EQ(a.nnz_factor, b.nnz_factor);
  EXPECT_GT(b.min_pivot_ratio, 0);
  MachineRates rates;
  const Mesh mesh = test_mesh();  // CellPredictor keeps a reference to it
  CellPredictor pred(mesh, ThesisEditOptions{}, rates);
  const Prediction pm = pred.predict(mem), pd = pred.predict(disk);
  EXPECT_EQ(pd.factor_bytes, pm.factor_bytes);
  EXPECT_GT(pd.workspace_bytes, 0);
  EXPECT_LT(pd.total_bytes, pm.total_bytes - 0.8 * pm.factor_bytes);
  EXPECT_EQ(disk.factor_storage(), "disk");
  std::vector<std::string> words = disk.to_args();
  words.insert(words.begin(), "exe");
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  const Args parsed = parse_args(static_cast<int>(argv.size()), argv.data(), 1, {"--cell"});
  EXPECT_EQ(CellSpec::from_args(parsed).factor_dir, disk.factor_dir);
}

TEST(ChildRunner, FailingChildGivesAnErrorResult) {
  CellSpec s = spec_for("lap", "structured");
  s.mesh_path = "/nonexistent/missing.off";
  const CellResult r = run_cell_in_child(self_executable(), s, 60);
  EXPECT_EQ(r.status, "error");
  EXPECT_NE(r.message.find("missing.off"), std::string::npos) << r.message;
  EXPECT_EQ(r.exit, "exit 2");  // InputError
}

TEST(ChildRunner, ChildWithoutResultLineIsAnError) {
  const CellResult r = run_cell_in_child("/bin/false", spec_for("lap", "structured"), 10);
  EXPECT_EQ(r.status, "error");
  EXPECT_NE(r.message.find("exit 1"), std::string::npos) << r.message;
}

TEST(ChildRunner, CrashAndTimeoutAreReported) {
  const ChildRun crash = run_child({"/bin/sh", "-c", "echo partial; kill -SEGV $$"});
  EXPECT_EQ(crash.term_signal, SIGSEGV);
  EXPECT_FALSE(crash.ok());
  EXPECT_EQ(crash.out, "partial\n");
  const ChildRun slow = run_child({"/bin/sleep", "5"}, 0.2);
  EXPECT_TRUE(slow.timed_out);
  EXPECT_LT(slow.wall_s, 4);
  const ChildRun missing = run_child({"/nonexistent/exe"});
  EXPECT_EQ(missing.exit_code, 127);
}

TEST(ResultLine, RoundTripsEveryField) {
  CellResult r;
  r.status = "error";
  r.message = "a message with spaces, = signs and\na newline %";
  r.ordering = "metis-vertex-graph";
  r.init_s = 1.25;
  r.peak_rss_bytes = 123456789012.0;
  r.held_bytes = {{"K_upper", 1000}, {"A t", 2000}};
  const CellResult d = decode_result("noise\n" + encode_result(r) + "\n");
  EXPECT_EQ(d.status, r.status);
  EXPECT_EQ(d.message, r.message);
  EXPECT_EQ(d.ordering, r.ordering);
  EXPECT_DOUBLE_EQ(d.init_s, 1.25);
  EXPECT_DOUBLE_EQ(d.peak_rss_bytes, 123456789012.0);
  EXPECT_TRUE(std::isnan(d.frame_s));
  ASSERT_EQ(d.held_bytes.size(), 2u);
  EXPECT_EQ(d.held_bytes[1].first, "A t");
  EXPECT_THROW(decode_result("no result here\n"), Error);
}

TEST(ResultLine, CellsThatDidNotRunKeepTheCoreMeasures) {
  CellResult r;
  r.status = "#over";
  r.predicted.total_bytes = 7e9;
  bool has_init = false, has_pred = false;
  for (const Measure& m : measures(r)) {
    has_init |= m.name == "init_s" && std::isnan(m.value);
    has_pred |= m.name == "predicted_bytes" && m.value == 7e9;
  }
  EXPECT_TRUE(has_init);
  EXPECT_TRUE(has_pred);
}

TEST(ResultLine, MedianOfRepeatedRuns) {
  std::vector<CellResult> runs(3);
  runs[0].init_s = 3;
  runs[1].init_s = 1;
  runs[2].init_s = 2;
  runs[0].held_bytes = {{"K_upper", 10}};
  const CellResult m = median_of(runs);
  EXPECT_DOUBLE_EQ(m.init_s, 2);
  EXPECT_DOUBLE_EQ(m.runs, 3);
  EXPECT_TRUE(std::isnan(m.frame_s));
  ASSERT_EQ(m.held_bytes.size(), 1u);
  EXPECT_THROW(median_of({}), Error);
}

TEST(ThesisEdit, HandleAndAnchorsAtOppositeExtremes) {
  const Mesh m = test_mesh();
  const Edit e = make_thesis_edit(m);
  EXPECT_EQ(e.count(Role::Handle), 100);
  EXPECT_EQ(e.count(Role::Fixed), 100);
  EXPECT_EQ(e.count(Role::Free), m.num_vertices() - 200);
  // The bar's longest axis is z: handle at the top, anchors at the bottom.
  for (int v : e.vertices(Role::Handle)) EXPECT_GT(m.V(v, 2), 1.5);
  for (int v : e.vertices(Role::Fixed)) EXPECT_LT(m.V(v, 2), 1.5);
  const Vec3 t = e.transform.topRightCorner<3, 1>();
  EXPECT_NEAR(t.norm(), 0.2 * bbox_diagonal(m.V), 1e-12);
  const Mat3 R = e.transform.topLeftCorner<3, 3>();
  EXPECT_TRUE(R.isIdentity());
}

TEST(ThesisEdit, OverlappingAnchorsAreDropped) {
  const Mesh m = make_bar(2, 2, 4, 1, 1, 2);  // fewer than 200 vertices
  const Edit e = make_thesis_edit(m);
  EXPECT_GT(e.count(Role::Handle), 0);
  EXPECT_GT(e.count(Role::Fixed), 0);
  EXPECT_EQ(e.count(Role::Handle) + e.count(Role::Fixed) + e.count(Role::Free), m.num_vertices());
}

TEST(Stats, MedianAndPowerLaw) {
  EXPECT_DOUBLE_EQ(median({3, 1, 2}), 2);
  EXPECT_DOUBLE_EQ(median({4, 1, 2, 3}), 2.5);
  EXPECT_TRUE(std::isnan(median({})));
  std::vector<double> x{1e3, 1e4, 1e5, 1e6}, y;
  for (double v : x) y.push_back(2e-6 * std::pow(v, 1.5));
  const PowerFit f = fit_power_law(x, y);
  EXPECT_NEAR(f.exponent, 1.5, 1e-12);
  EXPECT_NEAR(f.coefficient, 2e-6, 1e-15);
  EXPECT_NEAR(f.r2, 1.0, 1e-12);
  EXPECT_EQ(f.points, 4);
  EXPECT_TRUE(std::isnan(fit_power_law({1}, {2}).exponent));
}

}  // namespace

// Cell mode first: the runner tests re-execute this binary as the measuring child.
int main(int argc, char** argv) {
  if (argc > 1 && std::string(argv[1]) == "--cell") return cell_main(argc, argv);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
