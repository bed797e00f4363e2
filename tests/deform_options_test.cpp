// The deform options' one table (methods/deform_options.h): every row complete and unique, every enum's text table
// a bijection, key=value text round-tripping, and resolve_options naming the backend once and refusing what the
// other options leave unused.
#include <algorithm>
#include <set>

#include <gtest/gtest.h>

#include "solvers/base/error.h"
#include "methods/deform_options.h"

using namespace db;

namespace {

template <class E>
void expect_bijection() {
  std::set<std::string> seen;
  for (const std::string& name : enum_names<E>()) {
    EXPECT_TRUE(seen.insert(name).second) << "repeated name " << name;
    EXPECT_EQ(to_string(parse_enum<E>(name)), name);
  }
  try {
    parse_enum<E>("no-such-value");
    ADD_FAILURE() << "an unknown name was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(enum_choices<E>()), std::string::npos) << e.what();
  }
}

std::string usage_error(const DeformOptions& o, const std::vector<std::string>& given) {
  try {
    resolve_options(o, given);
  } catch (const UsageError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(DeformOptions, EveryEnumTableIsABijection) {
  expect_bijection<Method>();
  expect_bijection<ConstraintMode>();
  expect_bijection<FrameMode>();
  expect_bijection<TfScale>();
  expect_bijection<FrameControl>();
  expect_bijection<Precision>();
  expect_bijection<Weights>();
  expect_bijection<Build>();
  expect_bijection<FrameStrategy>();
  expect_bijection<Orthonormalization>();
  EXPECT_EQ(enum_choices<Build>(), "dense, naive or structured");
}

TEST(DeformOptions, EveryRowIsCompleteAndUnique) {
  std::set<std::string> keys, flags;
  const DeformOptions defaults;
  for (const DeformOptionDef& d : deform_option_defs()) {
    SCOPED_TRACE(d.key);
    EXPECT_TRUE(keys.insert(d.key).second);
    EXPECT_TRUE(flags.insert(d.flag).second);
    EXPECT_EQ(d.flag.rfind("--", 0), 0u);
    EXPECT_FALSE(d.help.empty());
    ASSERT_TRUE(d.check && d.set && d.get && d.unused);
    // The default's text passes its own check and sets the default again.
    std::string text = d.get(defaults);
    if (text.empty()) continue;
    EXPECT_EQ(d.check(text), "");
    DeformOptions o;
    set_deform_option(o, d.key, text);
    EXPECT_TRUE(deform_option_items(o).empty()) << d.key << "=" << text << " is not the default";
  }
  EXPECT_NE(deform_options_markdown().find("`--lri-frame-control` (`lri_frame_control=`)"), std::string::npos);
}

TEST(DeformOptions, KeyValueTextRoundTrips) {
  const std::vector<std::pair<std::string, std::string>> items = {
      {"method", "lri"},        {"constraints", "soft"}, {"soft_weight", "2.5"},  {"lri_frames", "random"},
      {"lri_orthonormalize", "polar"}, {"lri_seed", "7"}, {"build", "naive"}, {"backend", "cholmod_supernodal"},
      {"ordering", "amd"},      {"frame_mode", "handle"}, {"memory_budget_mb", "100"}};
  DeformOptions o;
  for (const auto& [key, value] : items) set_deform_option(o, key, value);
  EXPECT_EQ(o.method, Method::Lri);
  EXPECT_EQ(o.lri_frames, FrameStrategy::Random);
  EXPECT_EQ(o.lri_seed, 7u);
  EXPECT_EQ(o.memory_budget, 100000000u);
  EXPECT_EQ(o.solver, "cholmod_supernodal");
  auto sorted = [](std::vector<std::pair<std::string, std::string>> v) {
    std::sort(v.begin(), v.end());
    return v;
  };
  EXPECT_EQ(sorted(deform_option_items(o)), sorted(items));
}

TEST(DeformOptions, TextIsCheckedAsOnTheCommandLine) {
  DeformOptions o;
  auto message = [&](const std::string& key, const std::string& value) {
    try {
      set_deform_option(o, key, value);
    } catch (const UsageError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(message("soft_weight", "nan"), "--soft-weight: nan is not a finite number");
  EXPECT_EQ(message("lri_seed", "2.5"), "--lri-seed: 2.5 is not a whole number");
  EXPECT_EQ(message("method", "nope"), "--method: 'nope' is not one of: lap, tf, lri");
  EXPECT_EQ(message("methd", "tf"), "unknown deform option 'methd'");
  EXPECT_EQ(message("refine_max_iterations", "1e3"), "");  // numbers as the command line takes them
  EXPECT_EQ(o.solver_options.max_iterations, 1000);
}

TEST(DeformOptions, TheSolverIsResolvedOnce) {
  DeformOptions o;
  EXPECT_EQ(resolve_options(o).solver, "multifrontal");
  o.build = Build::Dense;
  EXPECT_EQ(resolve_options(o).solver, "dense_llt");
  o = DeformOptions{};
  o.precision = Precision::Mixed;
  set_deform_option(o, "refine_tolerance", "1e-12");
  const DeformOptions r = resolve_options(o, {"precision", "refine_tolerance"});
  EXPECT_EQ(r.solver, kMixedBackend);
  EXPECT_EQ(r.solver_options.tolerance, 1e-12);  // the refinement's settings reach the backend that refines
  EXPECT_EQ(resolve_options(r).solver, kMixedBackend);  // resolving again changes nothing
  o.solver = "cholmod_supernodal";
  EXPECT_EQ(usage_error(o, {}), "--precision mixed is the multifrontal backend's (multifrontal_mixed), not "
                                "cholmod_supernodal");
  o = DeformOptions{};
  o.soft_weight = 0;  // set in code: checked as its text would be
  EXPECT_EQ(usage_error(o, {}), "--soft-weight: 0 is outside [1e-08, 1e+08]");
}

TEST(DeformOptions, AGivenOptionTheOthersLeaveUnusedIsRefused) {
  DeformOptions o;
  EXPECT_EQ(usage_error(o, {"lri_frames"}), "--lri-frames is for --method lri only, not lap");
  EXPECT_EQ(usage_error(o, {}), "");  // the same value, not given: the default
  o.method = Method::Lri;
  EXPECT_EQ(usage_error(o, {"weights"}), "--weights is not used by --method lri (its systems have no Laplacian weights)");
  EXPECT_EQ(usage_error(o, {"lri_seed"}), "--lri-seed is used by --lri-frames random only, not first");
  o.lri_frames = FrameStrategy::Random;
  EXPECT_EQ(usage_error(o, {"lri_seed"}), "");
  o = DeformOptions{};
  o.solver = "umfpack";
  o.solver_options.factor_dir = "/tmp";
  EXPECT_NE(usage_error(o, {"factor_dir"}).find("--factor-dir: umfpack cannot keep its factor out of core"),
            std::string::npos);
  o = DeformOptions{};
  o.build = Build::Dense;
  o.method = Method::Lri;
  EXPECT_EQ(usage_error(o, {}), "--build dense: lri offers the structured and naive builds only");
  o = DeformOptions{};
  o.tf_scale = TfScale::Normalized;  // set in code, not given: still refused with a method that has no TF scale
  EXPECT_EQ(usage_error(o, {}), "--tf-scale normalized is for --method tf only, not lap");
}
