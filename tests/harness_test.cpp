// The experiment harness: the cell protocol (specs, the result line, medians, the CSV schema rules), the runner
// (measurements come back from a fresh process; a failing, crashing or slow child is an error result, not a dead
// driver; budgets decide before anything runs; repeats give medians), the deformation and solver cells, mesh
// sources of the configs, the thesis edit and the power-law fit.
//
// This binary doubles as the cell child: run with "--cell ..." it measures one cell, as the drivers do.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "solvers/base/error.h"
#include "edit/edit.h"
#include "edit/edit_io.h"
#include "harness/budget.h"
#include "harness/cell.h"
#include "harness/csv_reader.h"
#include "harness/deform_cell.h"
#include "harness/driver.h"
#include "harness/mesh_source.h"
#include "harness/positions.h"
#include "harness/runner.h"
#include "harness/shards.h"
#include "harness/solver_cell.h"
#include "harness/stats.h"
#include "harness/subprocess.h"
#include "harness/thesis_edit.h"
#include "mesh/mesh_io.h"
#include "mesh/procedural.h"
#include "mesh/subdivision.h"
#include "exact_deformation.h"

namespace fs = std::filesystem;
using namespace db;
using namespace db::harness;

namespace {

// A closed box surface of 1178 vertices: big enough for 100 handle + 100 anchor vertices that do not overlap.
Mesh test_mesh() { return make_bar(8, 8, 24, 1.0, 1.0, 3.0); }

// A private temporary directory with the test mesh, removed at exit.
struct TempDir {
  fs::path dir = fs::temp_directory_path() / ("db_harness_test_" + std::to_string(::getpid()));
  std::string mesh;
  TempDir() {
    fs::create_directories(dir);
    mesh = (dir / "bar.off").string();
    write_mesh(mesh, test_mesh());
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};
const TempDir& temp() {
  static const TempDir t;
  return t;
}

DeformCell deform_cell(const std::string& method, const std::string& build) {
  DeformCell c;
  c.model = "bar";
  c.mesh = temp().mesh;
  set_deform_option(c.options, "method", method);
  set_deform_option(c.options, "build", build);
  set_deform_option(c.options, "backend", build == "dense" ? "dense_llt" : "multifrontal");
  set_deform_option(c.options, "constraints", "soft");
  c.frames = 5;
  return c;
}

// Cell kinds for the runner's own tests: "echo" returns its keys as measures, "fail" throws, "crash" dies by a
// signal, "sleep" sleeps, "count" appends a line to a file per run and returns the line count.
CellResult echo(const CellSpec& s) {
  CellResult r;
  for (const auto& [k, v] : s.items())
    if (k != "kind") r.set(k, std::stod(v), "unit_" + k);
  r.set_text("said", "hello world = 1%");
  return r;
}
CellResult fail(const CellSpec& s) { throw SolverError("singular: " + s.get("why", "no reason")); }
CellResult crash(const CellSpec&) {
  std::raise(SIGSEGV);
  return {};
}
CellResult sleep_cell(const CellSpec& s) {
  std::this_thread::sleep_for(std::chrono::duration<double>(s.real("seconds", 1, 0, 60)));
  return {};
}
CellResult count(const CellSpec& s) {
  const std::string path = s.get("file");
  { std::ofstream(path, std::ios::app) << "run\n"; }
  std::ifstream in(path);
  CellResult r;
  double n = 0;
  for (std::string line; std::getline(in, line);) ++n;
  r.set("count", n);
  return r;
}

std::vector<CellKind> kinds() {
  return {deform_kind(), solver_kind(), loop_subdivide_kind(), {"echo", echo}, {"fail", fail},
          {"crash", crash},  {"sleep", sleep_cell}, {"count", count}};
}

// ------------------------------------------------------------------------------------------------ the protocol
TEST(CellSpec, KeysAreCheckedLikeACommandLine) {
  CellSpec s("deform");
  s.set("frames", 20).set("drag", 0.25).set("mesh", "a b=c.off");
  EXPECT_EQ(s.kind(), "deform");
  EXPECT_EQ(s.get("mesh"), "a b=c.off");
  EXPECT_EQ(s.integer("frames", 1, 1, 100), 20);
  EXPECT_DOUBLE_EQ(s.real("drag", 0, 0, 1), 0.25);
  EXPECT_EQ(s.integer("absent", 7, 1, 100), 7);
  EXPECT_THROW(s.get("absent"), UsageError);
  EXPECT_THROW(s.integer("drag", 1, 0, 10), UsageError);   // 0.25 is not a whole number
  EXPECT_THROW(s.integer("frames", 1, 1, 10), UsageError);  // out of range
  s.set("bad", "nan");
  EXPECT_THROW(s.real("bad", 0, -1e9, 1e9), UsageError);
  EXPECT_THROW(s.check_keys({"frames", "drag", "mesh"}), UsageError);  // "bad" is unknown
  EXPECT_NO_THROW(s.check_keys({"frames", "drag", "mesh", "bad"}));
  EXPECT_THROW(s.set("has space", "x"), UsageError);
  const CellSpec back = CellSpec::from_args(s.to_args());
  EXPECT_EQ(back.items(), s.items());
  EXPECT_THROW(CellSpec::from_args({"kind=x", "novalue"}), UsageError);
  EXPECT_THROW(CellSpec::from_args({"a=1", "a=2"}), UsageError);
}

TEST(ResultLine, RoundTripsMeasuresUnitsAndStrings) {
  CellResult r;
  r.status = "error";
  r.message = "a message with spaces, = signs and\na newline %";
  r.set("init_s", 1.25, "s");
  r.set("peak_rss_bytes", 123456789012.0, "bytes");
  r.set("held_bytes:A t", 2000, "bytes");
  r.set("not_measured", std::nan(""));
  r.set_text("ordering_used", "metis vertex=graph");
  const CellResult d = decode_result("noise\n" + encode_result(r) + "\n");
  EXPECT_EQ(d.status, r.status);
  EXPECT_EQ(d.message, r.message);
  EXPECT_EQ(d.text("ordering_used"), "metis vertex=graph");
  ASSERT_EQ(d.measures.size(), 4u);
  EXPECT_EQ(d.measures[2].name, "held_bytes:A t");
  EXPECT_EQ(d.measures[2].unit, "bytes");
  EXPECT_DOUBLE_EQ(d.get("peak_rss_bytes"), 123456789012.0);
  EXPECT_TRUE(std::isnan(d.get("not_measured")));
  EXPECT_TRUE(d.has("not_measured"));
  EXPECT_TRUE(std::isnan(d.get("absent")));
  EXPECT_THROW(decode_result("no result here\n"), Error);
}

TEST(ResultLine, MedianOfRepeatedRunsByName) {
  std::vector<CellResult> runs(3);
  runs[0].set("init_s", 3, "s");
  runs[1].set("init_s", 1, "s");
  runs[2].set("init_s", 2, "s");
  runs[1].set("only_second", 5);
  runs[0].set_text("ordering_used", "amd");
  const CellResult m = median_of(runs);
  EXPECT_DOUBLE_EQ(m.get("init_s"), 2);
  EXPECT_EQ(m.text("ordering_used"), "amd");
  EXPECT_FALSE(m.has("only_second"));  // the first run's measures
  EXPECT_THROW(median_of({}), Error);
}

TEST(ResultLine, TidyMeasuresKeepTheSchemaForCellsThatDidNotRun) {
  const std::vector<MeasureDef> defs = {{"init_s", "s", Keep::Always},
                                        {"n", "count", Keep::IfRan},
                                        {"iterations", "count", Keep::IfMeasured},
                                        {"held_bytes:*", "bytes"}};
  CellResult ok;
  ok.set("held_bytes:K", 10, "bytes");
  ok.set("init_s", 1);
  auto names = [](const std::vector<Measure>& m) {
    std::vector<std::string> v;
    for (const auto& x : m) v.push_back(x.name);
    return v;
  };
  const std::vector<std::string> init = {"init_s", "init_min_s", "init_max_s", "init_reps"};  // with its spread
  std::vector<std::string> all = init;
  all.insert(all.end(), {"n", "held_bytes:K"});
  EXPECT_EQ(names(tidy_measures(ok, defs)), all);
  EXPECT_EQ(tidy_measures(ok, defs)[0].unit, "s");
  const CellResult over = CellResult::with_status("#over", "predicted too much");
  EXPECT_EQ(names(tidy_measures(over, defs)), init);
  EXPECT_TRUE(std::isnan(tidy_measures(over, defs)[0].value));
}

// Planted repeats: three runs of a cell, each with the frames of its drag, the first of them slower by design (run 1
// also had a frame that waited 40 ms on a descheduled worker), and an init measured once.
TEST(ResultLine, TimingsCarryTheirSpreadOverEveryRepeatOfEveryRun) {
  std::vector<CellResult> runs(3);
  set_spread(runs[0], "frame_s", {0.005, 0.001, 0.002, 0.003});
  set_spread(runs[1], "frame_s", {0.005, 0.002, 0.04, 0.003, 0.002});
  set_spread(runs[2], "frame_s", {0.005, 0.0015, 0.0025});
  const double init[] = {0.5, 0.7, 0.6};
  for (int i = 0; i < 3; ++i) {
    runs[i].set("init_s", init[i], "s");
    runs[i].set("n", 10, "count");
  }
  // One run: the median of all its frames; the spread of those after the first.
  EXPECT_DOUBLE_EQ(runs[1].get("frame_s"), 0.003);
  EXPECT_DOUBLE_EQ(runs[1].get("frame_min_s"), 0.002);
  EXPECT_DOUBLE_EQ(runs[1].get("frame_max_s"), 0.04);
  EXPECT_EQ(runs[1].get("frame_reps"), 4);
  const CellResult m = median_of(runs);
  EXPECT_DOUBLE_EQ(m.get("frame_s"), 0.0025);  // the median of the runs' medians 0.0025, 0.003, 0.0025
  EXPECT_DOUBLE_EQ(m.get("frame_min_s"), 0.001);
  EXPECT_DOUBLE_EQ(m.get("frame_max_s"), 0.04);
  EXPECT_EQ(m.get("frame_reps"), 9);  // every repeat of every run
  EXPECT_DOUBLE_EQ(m.get("init_s"), 0.6);
  EXPECT_DOUBLE_EQ(m.get("init_min_s"), 0.5);
  EXPECT_DOUBLE_EQ(m.get("init_max_s"), 0.7);
  EXPECT_EQ(m.get("init_reps"), 3);  // fresh children: none warms up
  EXPECT_FALSE(m.has("n_reps"));  // counts are exact: no spread
  EXPECT_FALSE(m.has("frame_min_min_s"));
  EXPECT_TRUE(is_spread_of_measure(m, "frame_max_s"));
  EXPECT_FALSE(is_spread_of_measure(m, "init_s"));
  EXPECT_TRUE(spread_flagged(Spread{m.get("frame_min_s"), m.get("frame_s"), m.get("frame_max_s"), 9}));
  EXPECT_FALSE(spread_flagged(Spread{m.get("init_min_s"), m.get("init_s"), m.get("init_max_s"), 3}));
}

TEST(ResultLine, SpreadNamesFollowTheMeasure) {
  EXPECT_EQ(spread_name("frame_s", "min"), "frame_min_s");
  EXPECT_EQ(spread_name("factorize_s", "max"), "factorize_max_s");
  EXPECT_EQ(spread_name("frame_cpu_s", "reps"), "frame_cpu_reps");
  EXPECT_THROW(spread_name("fps", "min"), Error);
  EXPECT_THROW(spread_name("frame_s", "mean"), Error);
}

TEST(ResultLine, TidyMeasuresFollowATimingWithItsSpread) {
  const std::vector<MeasureDef> defs = {{"init_s", "s", Keep::Always},
                                        {"solve_s", "s", Keep::IfMeasured},
                                        {"predicted_s", "s", Keep::Always, false}};
  std::vector<CellResult> runs(2);
  runs[0].set("init_s", 1, "s");
  runs[1].set("init_s", 3, "s");
  auto names = [](const std::vector<Measure>& m) {
    std::vector<std::string> v;
    for (const auto& x : m) v.push_back(x.name);
    return v;
  };
  const std::vector<Measure> t = tidy_measures(median_of(runs), defs);
  EXPECT_EQ(names(t), (std::vector<std::string>{"init_s", "init_min_s", "init_max_s", "init_reps", "predicted_s"}));
  EXPECT_EQ(t[3].unit, "count");
  EXPECT_EQ(t[3].value, 2);
  EXPECT_EQ(t[2].value, 3);
  // A cell that did not run keeps the Always rows, spread included (empty values).
  const std::vector<Measure> over = tidy_measures(CellResult::with_status("#over", "predicted too much"), defs);
  EXPECT_EQ(names(over), names(t));
  EXPECT_TRUE(std::isnan(over[1].value));
}

// ------------------------------------------------------------------------------------------------ the drivers
TEST(Driver, FailedCellsAreListedAndGiveTheExitCode) {
  FailedCells f("test");
  f.note("kind=echo", CellResult{});
  f.note("kind=big", CellResult::with_status("#over", "predicted 9 GiB; not attempted"));
  f.note("kind=slow", CellResult::with_status("#slow", "predicted 1e4 s; not attempted"));
  f.note("kind=same", CellResult::with_status("skipped", "same as the default ordering"));
  CellSpec solver_failed("fail");
  solver_failed.set("why", "planted");
  const CellResult measured = run_cell(self_executable(), solver_failed, RunOptions{});  // SolverError: exit 3
  ASSERT_EQ(measured.status, "error");
  f.note(solver_failed.text(), measured);
  EXPECT_EQ(f.exit_code(), 0);  // budget refusals, skipped cells and measured solver failures are no failures
  CellSpec bad("crash");
  const CellResult r = run_cell(self_executable(), bad, RunOptions{});  // a cell made to fail
  f.note(bad.text(), r);
  f.note(bad.text(), r);  // a result reused for another table is one cell
  EXPECT_EQ(f.size(), 1u);
  ::testing::internal::CaptureStderr();
  EXPECT_EQ(f.exit_code(), kCellsFailedExit);
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("1 cell(s) failed"), std::string::npos) << err;
  EXPECT_NE(err.find("FAILED kind=crash"), std::string::npos) << err;
  EXPECT_NE(err.find("(signal"), std::string::npos) << err;
}

// ------------------------------------------------------------------------------------------------ the runner
TEST(Runner, ReturnsTheChildsMeasuresAndAddsTheParents) {
  CellSpec s("echo");
  s.set("x", 1.5).set("y", 2);
  const CellResult r = run_cell(self_executable(), s, RunOptions{});
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_DOUBLE_EQ(r.get("x"), 1.5);
  EXPECT_EQ(r.text("said"), "hello world = 1%");
  EXPECT_EQ(r.exit, "exit 0");
  EXPECT_GT(r.get("peak_rss_bytes"), 0);
  EXPECT_GT(r.get("ru_maxrss_bytes"), 0);
  EXPECT_GT(r.get("cell_wall_s"), 0);
  EXPECT_EQ(r.get("runs"), 1);
  EXPECT_FALSE(std::isnan(r.get("load_avg_1m")));
  EXPECT_FALSE(r.has("blas_dgemm_before"));
}

TEST(Runner, FailuresAreResultsWithTheExitCode) {
  CellSpec f("fail");
  f.set("why", "pivot 0");
  const CellResult r = run_cell(self_executable(), f, RunOptions{});
  EXPECT_EQ(r.status, "error");
  EXPECT_NE(r.message.find("pivot 0"), std::string::npos) << r.message;
  EXPECT_EQ(r.exit, "exit 3");  // SolverError
  EXPECT_GT(r.get("peak_rss_bytes"), 0);
  const CellResult unknown = run_cell(self_executable(), CellSpec("no_such_kind"), RunOptions{});
  EXPECT_EQ(unknown.status, "error");
  EXPECT_EQ(unknown.exit, "exit 1");
  const CellResult none = run_cell("/bin/false", CellSpec("echo"), RunOptions{});
  EXPECT_EQ(none.status, "error");
  EXPECT_NE(none.message.find("exit 1"), std::string::npos) << none.message;
}

TEST(Runner, CrashAndTimeoutAreReported) {
  const CellResult crashed = run_cell(self_executable(), CellSpec("crash"), RunOptions{});
  EXPECT_EQ(crashed.status, "error");
  EXPECT_NE(crashed.exit.find("signal"), std::string::npos) << crashed.exit;
  RunOptions o;
  o.timeout_s = 0.3;
  CellSpec s("sleep");
  s.set("seconds", 5);
  const CellResult slow = run_cell(self_executable(), s, o);
  EXPECT_EQ(slow.status, "error");
  EXPECT_NE(slow.exit.find("timed out"), std::string::npos) << slow.exit;
  EXPECT_LT(slow.get("cell_wall_s"), 4);
  const ChildRun missing = run_child({"/nonexistent/exe"});
  EXPECT_EQ(missing.exit_code, 127);
}

TEST(Runner, BudgetsDecideBeforeAnythingRuns) {
  const std::string file = (temp().dir / "budget_runs.txt").string();
  CellSpec s("count");
  s.set("file", file);
  Prediction p;
  p.bytes = 5e9;
  p.seconds = 1;
  p.measures = {{"predicted_bytes", 5e9, "bytes"}};
  RunOptions o;
  o.memory_budget_bytes = 1e9;
  const CellResult over = run_cell(self_executable(), s, o, &p);
  EXPECT_EQ(over.status, "#over");
  EXPECT_NE(over.message.find("not attempted"), std::string::npos);
  EXPECT_DOUBLE_EQ(over.get("predicted_bytes"), 5e9);
  EXPECT_EQ(over.exit, "");
  o.memory_budget_bytes = 0;  // unlimited
  o.time_budget_s = 0.5;
  EXPECT_EQ(run_cell(self_executable(), s, o, &p).status, "#slow");
  EXPECT_FALSE(fs::exists(file));  // neither ran
  o.time_budget_s = 10;
  const CellResult ran = run_cell(self_executable(), s, o, &p);
  EXPECT_TRUE(ran.ok()) << ran.message;
  EXPECT_DOUBLE_EQ(ran.get("predicted_bytes"), 5e9);
}

TEST(Runner, RepeatsGiveTheMedianOfFreshChildren) {
  const std::string file = (temp().dir / "repeat_runs.txt").string();
  CellSpec s("count");
  s.set("file", file);
  RunOptions o;
  o.repeats = 3;
  const CellResult r = run_cell(self_executable(), s, o);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(r.get("runs"), 3);
  EXPECT_EQ(r.get("count"), 2);  // the median of 1, 2, 3
  EXPECT_FALSE(r.has("count_reps"));
  EXPECT_EQ(r.get("cell_wall_reps"), 3);  // the parent's timings: their spread over the children
  EXPECT_LE(r.get("cell_wall_min_s"), r.get("cell_wall_s"));
  EXPECT_LE(r.get("cell_wall_s"), r.get("cell_wall_max_s"));
  Prediction p;
  p.seconds = 100;
  o.repeat_max_s = 50;  // predicted above it: once
  EXPECT_EQ(run_cell(self_executable(), s, o, &p).get("runs"), 1);
}

TEST(Runner, MachineRatesAroundTheCell) {
  RunOptions o;
  o.machine_rates = true;
  const CellResult r = run_cell(self_executable(), CellSpec("echo"), o);
  ASSERT_TRUE(r.ok()) << r.message;
  for (const char* m : {"blas_dgemm_before", "blas_dgemm_after", "memory_read_before", "memory_read_after"})
    EXPECT_GT(r.get(m), 0.01) << m;
  const CellResult f = run_cell(self_executable(), CellSpec("fail"), o);
  EXPECT_TRUE(f.has("blas_dgemm_before"));
  EXPECT_FALSE(f.has("blas_dgemm_after"));  // only around a cell that succeeded
}

// ------------------------------------------------------------------------------------------------ deform cells
TEST(Shards, GroupsGoRoundRobinAndPartitionTheGrid) {
  const std::vector<std::string> groups = {"a", "a", "b", "c", "c", "c", "d", "e"};
  const auto s1 = shard_cells(groups, parse_shard("--shard", "1/2"));
  const auto s2 = shard_cells(groups, parse_shard("--shard", "2/2"));
  EXPECT_EQ(s1, (std::vector<std::size_t>{0, 1, 3, 4, 5, 7}));  // groups a, c, e
  EXPECT_EQ(s2, (std::vector<std::size_t>{2, 6}));              // groups b, d
  EXPECT_EQ(shard_cells(groups, Shard{}).size(), groups.size());
  EXPECT_TRUE(shard_cells(groups, parse_shard("--shard", "7/7")).empty());
  for (const char* bad : {"0/1", "2/1", "1/0", "1/10001", "a/2", "1/2x", "", "/", "-1/2"})
    EXPECT_THROW(parse_shard("--shard", bad), UsageError) << bad;
}

TEST(DeformCell, SpecRoundTripsAndRejectsUnknownKeys) {
  DeformCell c = deform_cell("tf", "structured");
  c.options.solver_options.factor_dir = "/tmp";
  c.out_mesh = "/tmp/x.ply";
  const DeformCell d = DeformCell::from_spec(c.to_spec());
  EXPECT_EQ(d.to_spec().items(), c.to_spec().items());
  EXPECT_EQ(d.factor_storage(), "disk");
  CellSpec bad = c.to_spec();
  bad.set("frame", 3);  // a misspelling
  EXPECT_THROW(DeformCell::from_spec(bad), UsageError);
  CellSpec both = c.to_spec();
  both.set("edit", "x.edit");
  EXPECT_THROW(DeformCell::from_spec(both), UsageError);
}

TEST(DeformCell, MeasuredInAChild) {
  const CellResult r = run_cell(self_executable(), deform_cell("tf", "structured").to_spec(), RunOptions{});
  ASSERT_EQ(r.status, "ok") << r.message;
  const double nv = test_mesh().num_vertices();
  EXPECT_EQ(r.get("vertices"), nv);
  EXPECT_EQ(r.get("n"), 3 * nv);  // soft constraints: every vertex is an unknown
  EXPECT_EQ(r.get("frames"), 5);
  for (const char* m : {"frame_s", "rhs_s", "solve_s", "write_s", "frame_cpu_s"}) {  // the frames after the first
    EXPECT_EQ(r.get(spread_name(m, "reps")), 4) << m;
    EXPECT_LE(r.get(spread_name(m, "min")), r.get(m)) << m;
    EXPECT_LE(r.get(m), r.get(spread_name(m, "max"))) << m;
  }
  EXPECT_EQ(r.get("init_reps"), 1);  // once per run, one run
  EXPECT_EQ(r.get("init_min_s"), r.get("init_s"));
  EXPECT_NEAR(r.get("init_s"), r.get("build_s") + r.get("analyze_s") + r.get("factorize_s"), 1e-9);
  EXPECT_NEAR(r.get("fps") * r.get("frame_s"), 1.0, 1e-12);
  EXPECT_GT(r.get("factor_bytes"), 0);
  EXPECT_GT(r.get("held_total_bytes"), 0);
  EXPECT_TRUE(r.has("held_bytes:K_upper"));
  EXPECT_GT(r.get("peak_rss_bytes"), r.get("baseline_rss_bytes"));
  EXPECT_GT(r.get("mean_displacement"), 0);  // the handle moved the mesh
  EXPECT_FALSE(r.text("ordering_used").empty());
}

// How far two soft-constrained deformations of `rest` by `e` (P, as a cell writes it: the last full frame) may lie
// apart, as a vertex's distance over `diag`: each is within exact::solve_bound(cond K) of the exact deformation,
// relative, in normalized coordinates (exact_deformation.h; the rest mesh's bounding box has diagonal 1 there), and
// one vertex's distance is at most the whole difference's Frobenius norm. Not another solve under a fixed epsilon:
// two builds, backends or frame modes round differently.
double cells_apart_bound(const Mesh& rest, const Edit& e, const std::string& method, const Points& P, double diag) {
  DeformOptions o;
  o.method = parse_enum<Method>(method);
  o.constraints = ConstraintMode::Soft;
  const double relative = 2 * exact::solve_bound(system_condition(rest, e, o));
  return relative * Normalization::fit(rest.V).apply(P).norm() * bbox_diagonal(rest.V) / diag;
}

// Two cells' mean displacements (over the rest diagonal) agree within cells_apart_bound of the thesis edit.
void expect_same_mean_displacement(const CellResult& a, const CellResult& b, const std::string& method,
                                   const std::string& mesh_written) {
  const Mesh rest = test_mesh();
  const double tol = cells_apart_bound(rest, make_thesis_edit(rest), method, read_mesh(mesh_written).V,
                                       bbox_diagonal(rest.V));
  EXPECT_WITHIN(std::abs(a.get("mean_displacement") - b.get("mean_displacement")), tol) << method;
}

TEST(DeformCell, BuildsAgreeOnTheDeformation) {
  DeformCell structured = deform_cell("lap", "structured");
  structured.out_mesh = (temp().dir / "builds_agree.ply").string();
  const CellResult d = run_cell(self_executable(), deform_cell("lap", "dense").to_spec(), RunOptions{});
  const CellResult s = run_cell(self_executable(), structured.to_spec(), RunOptions{});
  ASSERT_EQ(d.status, "ok") << d.message;
  ASSERT_EQ(s.status, "ok") << s.message;
  expect_same_mean_displacement(d, s, "lap", structured.out_mesh);
}

TEST(DeformCell, AnEditFileCellWritesItsMesh) {
  DeformCell c;
  c.model = "bar";
  c.edit = (fs::path(DEFORMBENCH_SOURCE_DIR) / "data" / "bs08" / "bar").string();
  c.options.method = Method::Lap;
  c.frames = 2;
  c.out_mesh = (temp().dir / "bar_lap.ply").string();
  const CellResult r = run_cell(self_executable(), c.to_spec(), RunOptions{});
  ASSERT_EQ(r.status, "ok") << r.message;
  EXPECT_EQ(r.text("constraints"), "hard");
  EXPECT_GT(r.get("handle"), 0);
  EXPECT_EQ(read_mesh(c.out_mesh).num_vertices(), r.get("vertices"));
}

// handle_frames=1: after the full drag the same factored system precomputes its handle responses and drags again;
// the two modes' last frames agree, for the thesis edit's affine drag and for an edit's per-vertex targets (the top of
// the bar lifted and bent, frame by frame): on the default backend to cells_apart_bound (the system's conditioning),
// and where both modes converge to the exact solution (multifrontal_refined), to 1e-12 of the diagonal.
TEST(DeformCell, HandleFramesEqualFullFramesForAffineAndPerVertexDrags) {
  const fs::path dir = temp().dir;
  write_mesh((dir / "bar_drag.off").string(), test_mesh());
  { std::ofstream(dir / "bar_drag_rest.edit") << "mesh = bar_drag.off\nroi = all\nhandle = box:-0.3,-0.3,2.9,0.3,0.3,4\n"
                                                   "transform = translate:0,0,0\n"; }
  const EditCase rest = load_edit_case((dir / "bar_drag_rest.edit").string());
  {
    std::ofstream t(dir / "bar_drag.txt");
    for (int f = 1; f <= 2; ++f)
      for (int v = 0; v < rest.mesh.num_vertices(); ++v)
        if (rest.edit.roles[v] == Role::Handle) {
          const Vec3 p = rest.mesh.V.row(v).transpose();
          t << p.x() << " " << p.y() + 0.1 * f * p.x() * p.x() << " " << p.z() + 0.2 * f << "\n";
        }
  }
  { std::ofstream(dir / "bar_drag.edit") << "mesh = bar_drag.off\nroi = all\nhandle = box:-0.3,-0.3,2.9,0.3,0.3,4\n"
                                              "targets = bar_drag.txt\n"; }
  for (const std::string backend : {"multifrontal", "multifrontal_refined"})
    for (const std::string method : {"lap", "tf"})
      for (bool targets : {false, true}) {
        SCOPED_TRACE(backend + " " + method + (targets ? " per-vertex targets" : " affine"));
        DeformCell c = deform_cell(method, "structured");
        c.options.solver = backend;
        c.frames = 3;
        c.handle_frames = true;
        c.out_mesh = (dir / "handle_vs_full.ply").string();
        if (targets) {
          c.mesh.clear();
          c.edit = (dir / "bar_drag.edit").string();
        }
        const CellResult r = run_cell(self_executable(), c.to_spec(), RunOptions{});
        ASSERT_EQ(r.status, "ok") << r.message;
        if (backend == "multifrontal_refined") {
          EXPECT_WITHIN(r.get("handle_vs_full"), 1e-12);
        } else {
          const Points full = read_mesh(c.out_mesh).V;  // handle_vs_full is over the full frame's diagonal
          const Mesh rest = test_mesh();                // bar_drag.off too
          const Edit e = targets ? load_edit_case((dir / "bar_drag.edit").string()).edit : make_thesis_edit(rest);
          EXPECT_WITHIN(r.get("handle_vs_full"), cells_apart_bound(rest, e, method, full, bbox_diagonal(full)));
        }
        EXPECT_GT(r.get("mean_displacement"), 0);
        EXPECT_GT(r.get("precompute_cpu_s"), 0);
        EXPECT_GT(r.get("response_bytes"), 0);
      }
}

// Out of core (the factor in a scratch file): the deformation is the same, and the prediction the budget is
// checked against leaves the factor's values out while still reporting them.
TEST(DeformCell, OutOfCoreAgreesAndIsPredictedWithoutTheFactor) {
  DeformCell mem = deform_cell("tf", "structured"), disk = mem;
  disk.options.solver_options.factor_dir = fs::temp_directory_path().string();
  disk.out_mesh = (temp().dir / "out_of_core.ply").string();
  const CellResult a = run_cell(self_executable(), mem.to_spec(), RunOptions{});
  const CellResult b = run_cell(self_executable(), disk.to_spec(), RunOptions{});
  ASSERT_EQ(a.status, "ok") << a.message;
  ASSERT_EQ(b.status, "ok") << b.message;
  expect_same_mean_displacement(a, b, "tf", disk.out_mesh);
  EXPECT_EQ(a.get("nnz_factor"), b.get("nnz_factor"));
  EXPECT_GT(b.get("min_pivot_ratio"), 0);
  const Mesh mesh = test_mesh();  // CellPredictor keeps a reference to it
  CellPredictor pred(mesh, ThesisEditOptions{}, MachineRates{});
  const DeformPrediction pm = pred.predict(mem), pd = pred.predict(disk);
  EXPECT_EQ(pd.factor_bytes, pm.factor_bytes);
  EXPECT_GT(pd.workspace_bytes, 0);
  EXPECT_LT(pd.total_bytes, pm.total_bytes - 0.8 * pm.factor_bytes);
}

TEST(Budget, PredictionsOrderTheBuildsAndMatchTheDenseSize) {
  const Mesh m = test_mesh();
  CellPredictor pred(m, ThesisEditOptions{}, MachineRates{});  // default rates: byte predictions need none
  for (const char* system : {"lap", "tf"}) {
    const double b = std::string(system) == "tf" ? 3 : 1, n = b * m.num_vertices();
    const DeformPrediction d = pred.predict(deform_cell(system, "dense")),
                           nv = pred.predict(deform_cell(system, "naive")),
                           st = pred.predict(deform_cell(system, "structured"));
    EXPECT_DOUBLE_EQ(d.factor_bytes, n * n * 8) << system;
    EXPECT_GT(d.build_bytes, nv.build_bytes) << system;
    EXPECT_GT(nv.build_bytes, st.build_bytes) << system;
    EXPECT_GT(st.factor_flops, 0) << system;
    EXPECT_GT(st.seconds, 0) << system;
    EXPECT_GE(st.total_bytes, st.build_bytes + st.factor_bytes) << system;
    const Prediction g = st.generic();
    EXPECT_EQ(g.bytes, st.total_bytes);
    EXPECT_EQ(g.measures.size(), 7u);
  }
}

TEST(Budget, MeasuredRatesArePositive) {
  const MachineRates r = MachineRates::measure();
  EXPECT_GT(r.dense, 1e6);
  EXPECT_GT(r.sparse, 1e5);
  EXPECT_GT(r.stream, 1e6);
  EXPECT_GT(MachineRates::blas_gemm(), 1e8);
  EXPECT_GT(MachineRates::read_bandwidth(), 1e8);
}

// ------------------------------------------------------------------------------------------------ solver cells
namespace {

// A solver cell on the bar mesh (the other fields: SolverCell's defaults).
SolverCell bar_cell(const std::string& system, const std::string& backend, const std::string& ordering) {
  SolverCell c;
  c.model = "bar";
  c.mesh = temp().mesh;
  c.system = system;
  c.backend = backend;
  c.ordering = ordering;
  return c;
}

}  // namespace

// The least-squares row (QR of A) and a Cholesky of A^T A solve the same problem: the positions agree, and both
// recover the known solution of the synthetic right-hand side. The two solves round differently: they agree to
// twice the bound of a solve of K = A^T A's condition (QR's error is at most of the order eps (cond(A) + cond(A)^2
// ||r|| / (||A|| ||x||)), the normal equations' eps cond(A)^2; solvers/tests/exact_reference.h).
TEST(SolverCell, LeastSquaresAgreesWithCholesky) {
  for (const char* system : {"lap", "tf"}) {
    SolverCell chol = bar_cell(system, "cholmod_supernodal", "default");
    chol.solve_reps = 2;
    chol.factor_reps = 1;
    chol.rep_seconds = 1.0;
    chol.positions = (temp().dir / (std::string("chol_") + system + ".pos")).string();
    SolverCell qr = chol;
    qr.backend = kLeastSquaresBackend;
    qr.positions = (temp().dir / (std::string("qr_") + system + ".pos")).string();
    const CellResult a = run_cell(self_executable(), chol.to_spec(), RunOptions{});
    const CellResult b = run_cell(self_executable(), qr.to_spec(), RunOptions{});
    ASSERT_TRUE(a.ok()) << a.message;
    ASSERT_TRUE(b.ok()) << b.message;
    const Points A = read_positions(chol.positions), B = read_positions(qr.positions);
    const double tol = 2 * exact::solve_bound(exact::condition_number(build_thesis_system(temp().mesh, system).K));
    EXPECT_WITHIN(exact::rel(B, A), tol) << system;
    EXPECT_LT(a.get("error_exact"), 1e-8) << system;
    EXPECT_LT(b.get("error_exact"), 1e-8) << system;
    EXPECT_LT(b.get("residual"), 1e-10) << system;
    EXPECT_EQ(b.get("analyze_s"), 0);
    EXPECT_GT(b.get("factor_bytes"), 0);
    for (const char* m : {"factorize_s", "solve_s", "factorize_cpu_s", "solve_cpu_s"}) {  // over the repetitions
      EXPECT_GE(a.get(spread_name(m, "reps")), 1) << m;
      EXPECT_LE(a.get(spread_name(m, "reps")), std::string(m).rfind("solve", 0) == 0 ? 2 : 1) << m;
      EXPECT_LE(a.get(spread_name(m, "min")), a.get(m)) << m;
      EXPECT_LE(a.get(m), a.get(spread_name(m, "max"))) << m;
    }
    EXPECT_EQ(solver_family(qr.backend), "least-squares");
  }
}

TEST(SolverCell, SpecRoundTripsAndVertexOrderingsAreNamed) {
  SolverCell c = bar_cell("tf", "multifrontal", "vertex-metis");
  c.solve_reps = 1;
  c.factor_reps = 1;
  c.rep_seconds = 0.1;
  c.seed = 3;
  EXPECT_EQ(SolverCell::from_spec(c.to_spec()).to_spec().items(), c.to_spec().items());
  const CellResult r = run_cell(self_executable(), c.to_spec(), RunOptions{});
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(r.text("ordering_used"), "metis-vertex-graph");
  EXPECT_GT(r.get("order_s"), 0);
}

// ------------------------------------------------------------------------------------------------ configs
TEST(MeshSource, TiersSeriesAndErrors) {
  const MeshSource t = parse_mesh_source("planck=meshes/armadillo.off+loop1", "data");
  EXPECT_EQ(t.label, "planck");
  EXPECT_EQ(t.path, "data/meshes/armadillo.off");
  EXPECT_EQ(t.levels, 1);
  EXPECT_EQ(parse_mesh_source("mine=/abs/bunny.off", "data").path, "/abs/bunny.off");
  EXPECT_EQ(parse_mesh_source("mine=rel/bunny.off", "").path, "rel/bunny.off");
  const auto s = parse_mesh_series("hand_loop=meshes/hand.off+loop0..2", "d");
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s[0].label, "hand");
  EXPECT_EQ(s[2].label, "hand_loop2");
  EXPECT_EQ(s[2].series, "hand_loop");
  for (const char* bad : {"nolabel.off", "=x.off", "x=", "x=a.off+loop", "x=a.off+loop9", "x=a.off+loop2..1",
                          "x=a.off+loop1..2"})
    EXPECT_THROW(parse_mesh_source(bad, ""), UsageError) << bad;
  EXPECT_THROW(select_sources({t}, {"plank"}), UsageError);
  EXPECT_THROW(select_sources({t, t}, {}), UsageError);  // two tiers of one name
  EXPECT_EQ(select_sources({t}, {}).size(), 1u);
}

TEST(MeshSource, LoopLevelsAreGeneratedInAChildAndCached) {
  const MeshSource s = parse_mesh_source("bar1=" + temp().mesh + "+loop1", "");
  const std::string cache = (temp().dir / "cache").string();
  const std::string path = resolve_mesh(s, (temp().dir / "no_generated").string(), cache, self_executable());
  EXPECT_EQ(fs::path(path).filename(), "bar_loop1.off");
  EXPECT_EQ(read_mesh(path).num_vertices(), loop_subdivide(test_mesh(), 1).num_vertices());
  EXPECT_EQ(resolve_mesh(s, "", cache, "/nonexistent/exe"), path);  // cached: no child needed
  EXPECT_THROW(resolve_mesh(parse_mesh_source("x=/nonexistent.off", ""), "", cache, self_executable()), InputError);
}

TEST(Positions, RoundTripAndTruncation) {
  Points V = test_mesh().V;
  const std::string p = (temp().dir / "v.pos").string();
  write_positions(p, V);
  EXPECT_EQ(read_positions(p), V);
  fs::resize_file(p, fs::file_size(p) - 8);
  EXPECT_THROW(read_positions(p), InputError);
  EXPECT_THROW(read_positions(temp().mesh), InputError);
}

// The harness's readers open as core/input_file.h does: a FIFO is refused before it is opened for reading (before,
// the open blocked for ever: no writer comes), a file without line ends is refused at the line cap instead of being
// read whole, an empty CSV is an error naming the file, and a positions file's row count is checked against its size.
TEST(HarnessReaders, SpecialFilesAndBadSizesAreRefusedWithoutBlocking) {
  const fs::path dir = temp().dir / "readers";
  fs::create_directories(dir);
  const std::string fifo_csv = (dir / "fifo.csv").string(), fifo_pos = (dir / "fifo.pos").string();
  ASSERT_EQ(::mkfifo(fifo_csv.c_str(), 0600), 0);
  ASSERT_EQ(::mkfifo(fifo_pos.c_str(), 0600), 0);
  EXPECT_THROW(read_csv(fifo_csv), InputError);
  EXPECT_THROW(read_positions(fifo_pos), InputError);
  EXPECT_THROW(read_csv(dir.string()), InputError) << "a directory";
  const std::string empty = (dir / "empty.csv").string(), endless = (dir / "endless.csv").string();
  std::ofstream(empty).close();
  EXPECT_THROW(read_csv(empty), InputError);
  std::ofstream(endless) << std::string(harness::kMaxCsvLine + 1, 'x');
  try {
    read_csv(endless);
    FAIL() << "a line over the cap was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("line 1"), std::string::npos) << e.what();
  }
  const std::string ok = (dir / "ok.csv").string();
  std::ofstream(ok) << "a,b\n1,2\n\n3\n";
  const std::vector<CsvRow> rows = read_csv(ok);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].at("b"), "2");
  EXPECT_EQ(rows[1].count("b"), 0u);
  // A row count far beyond the file's size is refused before anything is allocated for it.
  const std::string huge = (dir / "huge.pos").string();
  {
    std::ofstream out(huge, std::ios::binary);
    const std::int64_t rows_declared = std::int64_t(1) << 60;
    out.write("DBPOS001", 8);
    out.write(reinterpret_cast<const char*>(&rows_declared), sizeof rows_declared);
  }
  EXPECT_THROW(read_positions(huge), InputError);
}

// ------------------------------------------------------------------------------------------------ the rest
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

TEST(Stats, SpreadOfRepeats) {
  const Spread s = spread({0.009, std::nan(""), 0.001, 0.0012, 0.0011});  // a warm-up repeat, then three
  EXPECT_DOUBLE_EQ(s.median, 0.00115);  // of all four
  EXPECT_DOUBLE_EQ(s.min, 0.001);       // the range and the count: after the first
  EXPECT_DOUBLE_EQ(s.max, 0.0012);
  EXPECT_EQ(s.count, 3);  // NaN is no repeat
  EXPECT_FALSE(spread_flagged(s));
  EXPECT_TRUE(spread_flagged(spread({0.001, 0.001, 0.0021})));  // more than 2x apart after the first
  EXPECT_FALSE(spread_flagged(spread({0.001, 0.001, 0.002})));  // 2x: not more
  const Spread two = spread({0.004, 0.001});  // under three repeats every one counts
  EXPECT_EQ(two.count, 2);
  EXPECT_TRUE(spread_flagged(two));
  EXPECT_FALSE(spread_flagged(spread({0.001})));
  EXPECT_EQ(spread({}).count, 0);
  EXPECT_TRUE(std::isnan(spread({}).median));
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
  // Three points fit a line closely whatever the law: no fit below kMinFitPoints, the count still reported.
  const PowerFit three = fit_power_law({1e3, 1e4, 1e5}, {1, 30, 50});
  EXPECT_TRUE(std::isnan(three.exponent));
  EXPECT_TRUE(std::isnan(three.r2));
  EXPECT_EQ(three.points, 3);
}

}  // namespace

// Cell mode first: the runner tests re-execute this binary as the measuring child.
int main(int argc, char** argv) {
  if (is_cell_invocation(argc, argv)) return cell_main(argc, argv, kinds());
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
