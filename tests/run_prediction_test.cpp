// methods/run_prediction.h: the calibration's fits (exact through their points, clamped), its file round trip and
// refusals, and the predicted factor counts against the factorization a run does.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include "methods/deform_options.h"
#include "methods/deformer.h"
#include "methods/run_prediction.h"
#include "mesh/procedural.h"
#include "solvers/base/error.h"

namespace db {
namespace {

TEST(PhaseRate, PassesThroughEveryCalibrationPoint) {
  const PhaseRate r = PhaseRate::fit({{4e6, 0.3}, {1e6, 0.1}, {16e6, 0.6}});  // any order
  ASSERT_EQ(r.points.size(), 3u);
  EXPECT_EQ(r.points.front().first, 1e6);
  EXPECT_EQ(r.seconds(4e6), 0.3);  // (u / u_i)^k = 1 exactly at a point
  EXPECT_EQ(r.seconds(16e6), 0.6);
  EXPECT_NEAR(r.seconds(1e6), 0.1, 1e-15);
  EXPECT_NEAR(r.seconds(2e6), 0.1 * std::pow(2.0, std::log(3.0) / std::log(4.0)), 1e-15);  // first segment's power
  EXPECT_NEAR(r.seconds(64e6), 0.6 * std::pow(4.0, 0.5), 1e-15);  // beyond: the last segment's power (k = 0.5)
}

TEST(PhaseRate, GrowsAtMostLinearlyBeyondTheLargestSize) {
  const PhaseRate r = PhaseRate::fit({{1e6, 0.1}, {2e6, 0.24}});  // superlinear between the two sizes
  EXPECT_NEAR(r.seconds(1.5e6), 0.24 * std::pow(0.75, std::log(2.4) / std::log(2.0)), 1e-15);
  EXPECT_NEAR(r.seconds(8e6), 0.24 * 4, 1e-15);  // beyond it: linear
}

TEST(PhaseRate, ClampsTheExponentAndStaysLinearWithOnePoint) {
  const double flat = PhaseRate::kMinExponent, steep = PhaseRate::kMaxExponent;
  EXPECT_NEAR(PhaseRate::fit({{1e6, 0.2}, {4e6, 0.2}}).seconds(1e6), 0.2 * std::pow(0.25, flat), 1e-15);
  EXPECT_NEAR(PhaseRate::fit({{1e6, 0.1}, {2e6, 1.0}}).seconds(1e6), 1.0 * std::pow(0.5, steep), 1e-15);
  const PhaseRate one = PhaseRate::fit({{2e6, 0.4}, {3e6, 0.0}});  // a point without time is dropped
  ASSERT_EQ(one.points.size(), 1u);
  EXPECT_EQ(one.seconds(1e6), 0.2);
  EXPECT_EQ(PhaseRate{}.seconds(1e6), 0.0);  // uncalibrated: no time, never NaN
  EXPECT_EQ(one.seconds(0), 0.0);
}

TEST(PhaseRate, TextRoundTripsAndBadTextIsRefused) {
  const PhaseRate r = PhaseRate::fit({{3491502624, 0.229077685}, {26470746.5, 1.0 / 3}});
  const PhaseRate back = PhaseRate::parse(r.text());
  EXPECT_EQ(back.points, r.points);
  EXPECT_TRUE(PhaseRate::parse("").points.empty());
  for (const char* bad : {"1", "1:", ":1", "1:2;", "1:-2", "1:nan", "1x:2", "2:1;2:3", "0:1"})
    EXPECT_THROW(PhaseRate::parse(bad), InputError) << bad;
}

std::string temp_path(const char* name) { return ::testing::TempDir() + name; }

TEST(MachineCalibration, RoundTripsExactly) {
  MachineCalibration c;
  BackendRates r;
  r.build = PhaseRate::fit({{1.5e7, 0.013}, {9.1e7, 0.07}});
  r.analyze = PhaseRate::fit({{0.003, 0.004}, {0.031, 0.05}});
  r.factorize = PhaseRate::fit({{3.3e8, 0.021}, {3.26e9, 0.19}, {2.9e10, 1.1}});
  r.peak_per_factor = 0.7077825396093732;
  r.peak_fixed_bytes = 1234567.5;
  c.rates[MachineCalibration::key("multifrontal", Build::Structured, Method::Tf)] = r;
  c.provenance = "test, with a comma";
  const std::string path = temp_path("calibration_roundtrip.csv");
  c.save(path);
  const MachineCalibration back = MachineCalibration::load(path);
  const std::optional<BackendRates> got = back.find("multifrontal", Build::Structured, Method::Tf);
  ASSERT_TRUE(got);
  EXPECT_EQ(got->build.points, r.build.points);
  EXPECT_EQ(got->analyze.points, r.analyze.points);
  EXPECT_EQ(got->factorize.points, r.factorize.points);
  EXPECT_EQ(got->peak_per_factor, r.peak_per_factor);
  EXPECT_EQ(got->peak_fixed_bytes, r.peak_fixed_bytes);
  EXPECT_EQ(back.provenance, c.provenance);
  EXPECT_EQ(back.find("multifrontal", Build::Structured, Method::Lri)->factorize.points,
            got->factorize.points);  // LRI takes TF's rates
  EXPECT_FALSE(back.find("multifrontal", Build::Structured, Method::Lap));
  EXPECT_EQ(back.find("multifrontal", Build::Structured, Method::Tf, "metis")->analyze.points,
            got->analyze.points);  // no key of its own: the default's
  std::remove(path.c_str());
}

TEST(MachineCalibration, AnOrderingMeasuredApartHasItsOwnBuildAndAnalysis) {
  MachineCalibration c;
  BackendRates base, metis;
  base.build = PhaseRate::fit({{1e6, 0.01}});
  metis.build = PhaseRate::fit({{1e6, 0.005}});
  base.analyze = PhaseRate::fit({{0.1, 0.05}});
  base.factorize = PhaseRate::fit({{1e9, 0.2}, {1e10, 1.0}});
  base.peak_per_factor = 1;
  metis.analyze = PhaseRate::fit({{0.1, 0.1}});
  metis.factorize = PhaseRate::fit({{1e9, 0.3}});
  metis.peak_per_factor = 2;
  c.rates[MachineCalibration::key("cholmod_supernodal", Build::Structured, Method::Lap)] = base;
  c.rates[MachineCalibration::key("cholmod_supernodal", Build::Structured, Method::Lap, "metis")] = metis;
  EXPECT_EQ(MachineCalibration::key("cholmod_supernodal", Build::Structured, Method::Lap, "default"),
            "cholmod_supernodal/structured/lap");
  const auto m = c.find("cholmod_supernodal", Build::Structured, Method::Lap, "metis");
  EXPECT_EQ(m->build.points, metis.build.points);          // the ordering's own build
  EXPECT_EQ(m->analyze.points, metis.analyze.points);      // and analysis
  EXPECT_EQ(m->factorize.points, base.factorize.points);  // the rest as the default ordering's
  EXPECT_EQ(m->peak_per_factor, 1);
  EXPECT_EQ(c.find("cholmod_supernodal", Build::Structured, Method::Lap, "amd")->analyze.points, base.analyze.points);
  EXPECT_EQ(c.find("cholmod_supernodal", Build::Structured, Method::Lap, "amd")->build.points, base.build.points);
  const std::string path = temp_path("calibration_orderings.csv");
  c.save(path);
  EXPECT_EQ(MachineCalibration::load(path).find("cholmod_supernodal", Build::Structured, Method::Lap, "metis")
                ->analyze.points,
            metis.analyze.points);
  std::remove(path.c_str());
}

TEST(MachineCalibration, NoFactorizationOutrunsTheDenseCholesky) {
  MachineCalibration c;
  BackendRates mf, potrf;
  mf.factorize = PhaseRate::fit({{1e9, 0.1}, {1e10, 0.5}});  // 10, then 20 GFlop/s: the rate still grows
  potrf.factorize = PhaseRate::fit({{1e9, 0.05}, {8e9, 0.32}});  // 20, then 25 GFlop/s
  c.rates[MachineCalibration::key("multifrontal", Build::Structured, Method::Tf)] = mf;
  c.rates[MachineCalibration::key("lapack_potrf", Build::Dense, Method::Tf)] = potrf;
  EXPECT_EQ(c.dense_flop_rate(), 8e9 / 0.32);
  const auto r = c.find("multifrontal", Build::Structured, Method::Tf);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->peak_flop_rate, 8e9 / 0.32);
  EXPECT_EQ(MachineCalibration{}.dense_flop_rate(), 0);
}

TEST(MachineCalibration, RefusesAnOlderLayoutAndBadValues) {
  const std::string path = temp_path("calibration_old.csv");
  std::ofstream(path) << "key,factor_s_per_unit,factor_units,factor_exponent,analyze_ratio,build_s_per_unit,"
                         "peak_per_factor\nmultifrontal/structured,1e-10,1e9,0.3,1,1e-9,0.7\n";
  EXPECT_THROW(MachineCalibration::load(path), InputError);
  for (const char* bad : {"1:nan", "1:-1", "1x:2", "1;2"}) {
    std::ofstream(path) << "key,build,analyze,factorize,peak_per_factor,peak_fixed_bytes\nmultifrontal/structured/tf,"
                        << bad << ",1:1,1:1,0.7,0\n";
    EXPECT_THROW(MachineCalibration::load(path), InputError) << bad;
  }
  std::ofstream(path) << "key,build,analyze,factorize,peak_per_factor,peak_fixed_bytes\nmultifrontal/structured/tf,"
                         "1:1,1:1,1:1,-0.7,0\n";
  EXPECT_THROW(MachineCalibration::load(path), InputError);
  std::remove(path.c_str());
  EXPECT_TRUE(MachineCalibration::load(temp_path("no_such_calibration.csv")).empty());
}

// The predictor's count is the backend's own analysis of the vertex graph in the run's order: for scalar systems
// (LAP) it is the factor the run makes, exactly.
TEST(RunPrediction, CountsTheFactorALapRunMakes) {
  const Mesh plane = make_bumpy_plane(24, 24, 1.0, 0.05, 3);
  Edit edit;
  edit.roles.assign(plane.num_vertices(), Role::Free);
  for (int v : {0, 1, 25}) edit.roles[v] = Role::Handle;
  for (const char* solver : {"multifrontal", "cholmod_supernodal", "cholmod_simplicial_ldlt"}) {
    DeformOptions o;
    set_deform_option(o, "method", "lap");
    set_deform_option(o, "constraints", "soft");
    o.solver = solver;
    const RunPrediction p = predict_run(plane, edit, resolve_options(o), MachineCalibration{});
    const auto run = make_deformer(plane, edit, o);
    ASSERT_EQ(run->systems().size(), 1u);
    EXPECT_EQ(p.factor_nnz, static_cast<double>(run->systems()[0].factor.nnz_factor)) << solver;
    EXPECT_EQ(p.n, static_cast<double>(run->systems()[0].n)) << solver;
    EXPECT_TRUE(std::isnan(p.init_s)) << "uncalibrated: no time";
    EXPECT_GT(p.peak_bytes, p.base_bytes + p.build_bytes) << solver;
  }
}

TEST(RunPrediction, AFactorizationTakesAtLeastItsFlopsAtTheDenseRate) {
  const Mesh plane = make_bumpy_plane(24, 24, 1.0, 0.05, 3);
  Edit edit;
  edit.roles.assign(plane.num_vertices(), Role::Free);
  for (int v : {0, 1, 25}) edit.roles[v] = Role::Handle;
  DeformOptions o;
  set_deform_option(o, "method", "lap");
  set_deform_option(o, "constraints", "soft");
  MachineCalibration c;
  BackendRates fast, potrf;
  fast.factorize = PhaseRate::fit({{1e3, 1e-12}});  // a rate no machine has
  potrf.factorize = PhaseRate::fit({{2e9, 1.0}});   // 2 GFlop/s
  c.rates[MachineCalibration::key("multifrontal", Build::Structured, Method::Lap)] = fast;
  c.rates[MachineCalibration::key("lapack_potrf", Build::Dense, Method::Lap)] = potrf;
  const RunPrediction p = predict_run(plane, edit, resolve_options(o), c);
  ASSERT_GT(p.factor_flops, 0);
  EXPECT_EQ(p.factorize_s, p.factor_flops / 2e9);
  c.rates.erase(MachineCalibration::key("lapack_potrf", Build::Dense, Method::Lap));
  EXPECT_LT(predict_run(plane, edit, resolve_options(o), c).factorize_s, p.factorize_s) << "no bound without it";
}

}  // namespace
}  // namespace db
