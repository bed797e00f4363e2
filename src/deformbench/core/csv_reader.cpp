#include "core/csv_reader.h"

#include <fmt/format.h>

#include "core/input_file.h"
#include "solvers/base/error.h"

namespace db {

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> f;
  std::string cur;
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') cur += '"', ++i;
      else if (c == '"') quoted = false;
      else cur += c;
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      f.push_back(cur);
      cur.clear();
    } else if (c != '\r') {
      cur += c;
    }
  }
  f.push_back(cur);
  return f;
}

std::string each_csv_line(const std::string& path,
                          const std::function<void(int, const std::string&, const std::string&)>& fn) {
  InputFile in(path, "CSV", kMaxCsvBytes);
  std::string header;
  in.each_line(kMaxCsvLine, [&](int lineno, const std::string& line) {
    if (lineno == 1) header = line;
    else if (!line.empty()) fn(lineno, header, line);
  });
  if (header.empty()) throw InputError(fmt::format("{}: no header line (an empty CSV file)", path));
  return header;
}

std::vector<CsvRow> read_csv(const std::string& path) {
  std::vector<std::string> columns;
  std::vector<CsvRow> rows;
  each_csv_line(path, [&](int lineno, const std::string& header, const std::string& line) {
    if (columns.empty()) columns = split_csv_line(header);
    const auto f = split_csv_line(line);
    if (f.size() > columns.size())
      throw InputError(fmt::format("{}:{}: {} fields, the header has {}", path, lineno, f.size(), columns.size()));
    CsvRow row;
    for (std::size_t i = 0; i < f.size(); ++i) row[columns[i]] = f[i];
    rows.push_back(std::move(row));
  });
  return rows;
}

}  // namespace db
