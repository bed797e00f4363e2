#pragma once
//! Tidy CSV: one row per measurement, a fixed header, provenance columns appended to every row.
#include <string>
#include <utility>
#include <vector>

namespace db {

class CsvTable {
 public:
  using Row = std::vector<std::pair<std::string, std::string>>;

  //! Adds a row; its keys must match the first row's keys in order (provenance columns are appended here).
  //! \throw Error on a key mismatch.
  void add(Row row);
  bool empty() const { return rows_.empty(); }
  std::size_t size() const { return rows_.size(); }
  //! Writes header + rows atomically.
  void write(const std::string& path) const;

 private:
  std::vector<std::string> header_;
  std::vector<std::vector<std::string>> rows_;
};

//! Quotes a field when it holds a comma, quote or newline.
std::string csv_escape(const std::string& s);
//! Shortest round-trip representation of a double ("nan"/"inf" spelled out).
std::string num(double v);

}  // namespace db
