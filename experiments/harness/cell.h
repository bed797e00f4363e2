#pragma once
//! The one cell protocol of every experiment driver (Table 2-1, the solver study, the frames study, the edit
//! cases; later the tracking suite). A cell is
//!  - a spec: ordered key=value options (CellSpec), the key "kind" naming the measure function;
//!  - a measure function, run in a fresh child process (the driver re-executed with `--cell key=value ...`,
//!    harness/runner.h), which parses the spec and returns
//!  - a result (CellResult): a status, named measures (a number and a unit each) and named strings, sent back
//!    on one line "DBCELL status=ok m.n=1197 u.n=count t.ordering_used=amd ..." (encode_result).
//! The parent adds what only it can see (harness/runner.h). A grid is a plain list of specs.
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "core/spread.h"

namespace db::harness {

//! What to measure: ordered, unique keys. Values are strings; the accessors check numbers as the command
//! lines do (a spec is a command line of the child).
class CellSpec {
 public:
  CellSpec() = default;
  explicit CellSpec(const std::string& kind) { set("kind", kind); }

  //! Sets (or replaces) a key. \throw UsageError for an empty key or one with '=' or spaces.
  CellSpec& set(const std::string& key, const std::string& value);
  CellSpec& set(const std::string& key, const char* value) { return set(key, std::string(value)); }
  //! Numbers in the shortest form that reads back exactly.
  CellSpec& set(const std::string& key, double value);
  CellSpec& set(const std::string& key, int value) { return set(key, static_cast<double>(value)); }
  CellSpec& set(const std::string& key, std::size_t value) { return set(key, static_cast<double>(value)); }

  bool has(const std::string& key) const;
  std::string kind() const { return get("kind", ""); }
  //! \throw UsageError when the key is missing.
  std::string get(const std::string& key) const;
  std::string get(const std::string& key, const std::string& fallback) const;
  //! A finite number in [min, max]; `fallback` when the key is absent. \throw UsageError otherwise.
  double real(const std::string& key, double fallback, double min, double max) const;
  //! A whole number in [min, max]; `fallback` when the key is absent. \throw UsageError otherwise.
  long long integer(const std::string& key, long long fallback, long long min, long long max) const;
  //! \throw UsageError naming the first key that is not "kind" and not in `known` (a misspelled key is an error).
  void check_keys(const std::vector<std::string>& known) const;

  const std::vector<std::pair<std::string, std::string>>& items() const { return items_; }
  //! {"kind=deform", "mesh=...", ...}: the child's command line after "--cell".
  std::vector<std::string> to_args() const;
  //! \throw UsageError for an argument without '=' or a repeated key.
  static CellSpec from_args(const std::vector<std::string>& args);
  //! "kind=deform mesh=... ..." for logs.
  std::string text() const;

 private:
  std::vector<std::pair<std::string, std::string>> items_;
};

//! A named value for tidy (long) rows: measure, value, unit.
struct Measure {
  std::string name;
  double value;
  std::string unit;
};

//! What a cell gave. Measures keep their order; NaN = not measured.
struct CellResult {
  std::string status = "ok";  //!< ok | #over | #slow | error | skipped
  std::string message;        //!< why, for anything but ok
  std::string exit;           //!< parent: how the child ended ("exit 0", "signal 9 (Killed)", ...); "" = never ran
  std::vector<Measure> measures;
  std::vector<std::pair<std::string, std::string>> texts;  //!< named strings (e.g. "ordering_used")

  //! A result without measures: a cell that did not run, or failed before measuring.
  static CellResult with_status(const std::string& status, const std::string& message) {
    CellResult r;
    r.status = status;
    r.message = message;
    return r;
  }
  bool ok() const { return status == "ok"; }
  //! Sets (or replaces, keeping its place) a measure.
  void set(const std::string& name, double value, const std::string& unit = "");
  //! NaN when absent.
  double get(const std::string& name) const;
  bool has(const std::string& name) const;
  void erase(const std::string& name);
  void set_text(const std::string& name, const std::string& value);
  //! "" when absent.
  std::string text(const std::string& name) const;
};

//! "DBCELL status=ok message= m.n=1197 u.n=count t.ordering_used=amd" (values percent-encoded: one token each).
std::string encode_result(const CellResult& r);
//! Parses the last "DBCELL " line of a child's stdout. \throw Error when there is none or it is malformed.
CellResult decode_result(const std::string& child_stdout);

//! Sets `name` (a timed measure, "s") to the median of `samples` and its spread measures (spread_name).
void set_spread(CellResult& r, const std::string& name, const std::vector<double>& samples);
//! Whether `name` is the spread measure of a timed measure `r` has ("frame_min_s" when "frame_s" is there).
bool is_spread_of_measure(const CellResult& r, const std::string& name);

//! Measure-by-measure median of repeated runs of one cell (NaN where no run measured it), in the first run's
//! order; status, strings and exit from the first run. Timed measures (unit "s") get their spread over the runs
//! (spread_name): a run that carries its own spread (the frames of its drag) gives its least and largest repeat and
//! its count, so NAME_min_s / NAME_max_s are over every repeat of every run and NAME_reps is their total, while
//! NAME_s is the median of the runs' medians. \throw Error for an empty list.
CellResult median_of(const std::vector<CellResult>& runs);

//! Which measures a CSV keeps for a cell.
enum class Keep {
  Always,      //!< every cell has the row (empty value where not measured), so every cell has the same rows
  IfRan,       //!< cells that ran (status ok), and any cell that measured it
  IfMeasured,  //!< only where measured (not NaN)
};
//! One measure of an experiment's CSV schema. A name ending in '*' stands for every measure of the result
//! whose name starts with the rest ("held_bytes:*"), in the result's order, with the result's units. A timed
//! measure (unit "s") is followed by its spread (spread_name: NAME_min_s, NAME_max_s, NAME_reps) under the same
//! keep rule, unless `spread` is false (a prediction, not a measurement).
struct MeasureDef {
  std::string name;
  std::string unit;
  Keep keep = Keep::IfRan;
  bool spread = true;
};
//! The measures of `r` a CSV writes, in the order of `defs` (units from `defs`).
std::vector<Measure> tidy_measures(const CellResult& r, const std::vector<MeasureDef>& defs);

}  // namespace db::harness
