#pragma once
//! Reading back the tidy CSVs the drivers and `deformbench deform --csv` write (core/csv.h): RFC 4180 quoting, no
//! embedded newlines.
#include <map>
#include <string>
#include <vector>

namespace db {

using CsvRow = std::map<std::string, std::string>;

//! The fields of one line (RFC 4180 quoting undone).
std::vector<std::string> split_csv_line(const std::string& line);

//! Every row as column -> value. \throw InputError when the file cannot be read or a row has more fields than
//! the header.
std::vector<CsvRow> read_csv(const std::string& path);

}  // namespace db
