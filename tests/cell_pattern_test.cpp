// Cell patterns and rules (harness/cell_pattern.h): the tracking suite written as data.
#include <gtest/gtest.h>

#include "solvers/base/error.h"
#include "harness/cell_pattern.h"

using namespace db;
using namespace db::harness;

TEST(CellPattern, ExpandsTheCrossProductTiersFirst) {
  const auto cells = expand_cell_pattern("deform hand,armadillo: method=lap,tf build=structured frames=3");
  ASSERT_EQ(cells.size(), 4u);
  EXPECT_EQ(cells[0].text(), "kind=deform model=hand method=lap build=structured frames=3");
  EXPECT_EQ(cells[1].text(), "kind=deform model=hand method=tf build=structured frames=3");
  EXPECT_EQ(cells[2].get("model"), "armadillo");
  EXPECT_EQ(cells[3].get("method"), "tf");
}

TEST(CellPattern, KindAndTiersOnly) {
  const auto cells = expand_cell_pattern("  solve   hand :  ");
  ASSERT_EQ(cells.size(), 1u);
  EXPECT_EQ(cells[0].text(), "kind=solve model=hand");
}

TEST(CellPattern, MalformedPatternsAreUsageErrors) {
  for (const char* bad : {"deform hand method=lap", "deform: method=lap", "deform a b: method=lap",
                          "deform hand: method", "deform hand: method=", "deform hand: =lap",
                          "deform hand: method=lap,,tf", "deform hand,: method=lap", "deform hand: model=x",
                          "deform hand: method=lap method=tf"})
    EXPECT_THROW(expand_cell_pattern(bad), UsageError) << bad;
}

TEST(CellRule, DefaultsFillOverridesReplace) {
  CellSpec tf = expand_cell_pattern("deform hand: method=tf ordering=metis").front();
  CellSpec lap = expand_cell_pattern("deform hand: method=lap").front();
  const CellRule r = parse_cell_rule("kind=deform method=tf: ordering=natural frames=2");
  EXPECT_TRUE(rule_matches(r, tf));
  EXPECT_FALSE(rule_matches(r, lap));
  CellSpec d = tf;
  EXPECT_TRUE(apply_cell_rule(r, d, false));
  EXPECT_EQ(d.get("ordering"), "metis");  // a default keeps what the cell sets
  EXPECT_EQ(d.get("frames"), "2");
  EXPECT_TRUE(apply_cell_rule(r, tf, true));
  EXPECT_EQ(tf.get("ordering"), "natural");
  EXPECT_FALSE(apply_cell_rule(r, lap, true));
  EXPECT_FALSE(lap.has("ordering"));
  const CellRule all = parse_cell_rule(": frames=5");
  EXPECT_TRUE(apply_cell_rule(all, lap, false));
  EXPECT_EQ(lap.get("frames"), "5");
}

TEST(CellRule, MalformedRulesAreUsageErrors) {
  for (const char* bad : {"kind=deform", "kind=deform:", "kind: frames=2", "kind=deform: frames"})
    EXPECT_THROW(parse_cell_rule(bad), UsageError) << bad;
}
