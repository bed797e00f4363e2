#pragma once
//! A suite of cells written as data (data/experiments/track.toml), in two forms of one line each:
//!   pattern  "KIND TIER[,TIER...]: key=v1[,v2...] key=v ..."  one cell spec per combination of the listed
//!            values (the tiers first), with kind=KIND and model=TIER set; e.g.
//!            "deform hand,armadillo: method=lap,tf build=structured,naive" is 2 x 2 x 2 = 8 cells
//!   rule     "[key=value ...]: key=value ..."  the keys after the colon, for the specs that hold every key=value
//!            before it (all specs when there is none); e.g. "kind=deform method=tf: ordering=natural"
//! A rule applied as a default sets only keys a spec lacks; applied as an override it replaces them.
#include <string>
#include <utility>
#include <vector>

#include "harness/cell.h"

namespace db::harness {

using KeyValues = std::vector<std::pair<std::string, std::string>>;

//! Expands a pattern. \throw UsageError naming the pattern for a missing colon, kind or tier, a token without
//! '=', an empty value or a key given twice.
std::vector<CellSpec> expand_cell_pattern(const std::string& text);

struct CellRule {
  KeyValues when;  //!< every pair must be in the spec
  KeyValues set;   //!< what the rule sets
  std::string text;
};

//! Parses a rule. \throw UsageError naming the rule for a missing colon, nothing to set or a token without '='.
CellRule parse_cell_rule(const std::string& text);
bool rule_matches(const CellRule& rule, const CellSpec& spec);
//! Applies `rule` to `spec` when it matches: every key (override), or only the keys `spec` lacks (default).
//! Returns whether it matched.
bool apply_cell_rule(const CellRule& rule, CellSpec& spec, bool override);

}  // namespace db::harness
