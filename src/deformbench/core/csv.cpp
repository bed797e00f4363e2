#include "core/csv.h"

#include <cmath>

#include <fmt/format.h>

#include "solvers/base/atomic_file.h"
#include "solvers/base/error.h"
#include "core/provenance.h"

namespace db {

std::string csv_escape(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

std::string num(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return fmt::format("{}", v);
}

void CsvTable::add(Row row) {
  for (auto& kv : provenance().columns()) row.push_back(kv);
  if (header_.empty()) {
    for (auto& kv : row) header_.push_back(kv.first);
  } else {
    if (row.size() != header_.size()) throw Error("CSV row has a different number of columns than the header");
    for (std::size_t i = 0; i < row.size(); ++i)
      if (row[i].first != header_[i]) throw Error("CSV column mismatch: " + row[i].first + " vs " + header_[i]);
  }
  std::vector<std::string> values;
  values.reserve(row.size());
  for (auto& kv : row) values.push_back(std::move(kv.second));
  rows_.push_back(std::move(values));
}

void CsvTable::write(const std::string& path) const {
  write_atomically(path, [&](std::ostream& out) {
    for (std::size_t i = 0; i < header_.size(); ++i) out << (i ? "," : "") << csv_escape(header_[i]);
    out << '\n';
    for (const auto& r : rows_) {
      for (std::size_t i = 0; i < r.size(); ++i) out << (i ? "," : "") << csv_escape(r[i]);
      out << '\n';
    }
  });
}

}  // namespace db
