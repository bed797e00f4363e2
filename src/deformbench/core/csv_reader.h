#pragma once
//! Reading back the tidy CSVs the drivers and `deformbench deform --csv` write (core/csv.h): RFC 4180 quoting, no
//! embedded newlines.
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace db {

using CsvRow = std::map<std::string, std::string>;

//! The fields of one line (RFC 4180 quoting undone).
std::vector<std::string> split_csv_line(const std::string& line);

//! Bounds of a CSV read back: its size and a line's length (core/input_file.h checks them before reading).
constexpr std::uint64_t kMaxCsvBytes = std::uint64_t(1) << 30;
constexpr std::size_t kMaxCsvLine = std::size_t(1) << 20;

//! Opens `path` as core/input_file.h does (a regular file, no blocking open, at most kMaxCsvBytes, lines of at most
//! kMaxCsvLine) and calls fn(line number, header line, line) for each non-empty line after the header; returns the
//! header line.
//! \throw InputError naming the file when it cannot be read, exceeds a bound or has no header line.
std::string each_csv_line(const std::string& path,
                          const std::function<void(int, const std::string&, const std::string&)>& fn);

//! Every row as column -> value. \throw InputError when the file cannot be read (each_csv_line) or a row has more
//! fields than the header.
std::vector<CsvRow> read_csv(const std::string& path);

}  // namespace db
