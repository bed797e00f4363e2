#pragma once
//! The CSV reader lives in the library (core/csv_reader.h): `deformbench advise` reads its children's records with it.
#include "core/csv_reader.h"

namespace db::harness {

using db::CsvRow;
using db::each_csv_line;
using db::kMaxCsvBytes;
using db::kMaxCsvLine;
using db::read_csv;
using db::split_csv_line;

}  // namespace db::harness
