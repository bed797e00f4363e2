#include "harness/positions.h"

#include <cstdint>
#include <cstring>

#include <fmt/format.h>

#include "core/input_file.h"
#include "solvers/base/atomic_file.h"
#include "solvers/base/error.h"

namespace db::harness {
namespace {

constexpr char kMagic[8] = {'D', 'B', 'P', 'O', 'S', '0', '0', '1'};

// Up to n bytes (fewer only at the end of the file).
std::size_t read_full(InputFile& in, char* buf, std::size_t n) {
  std::size_t done = 0;
  for (std::size_t got; done < n && (got = in.read(buf + done, n - done)) > 0;) done += got;
  return done;
}

}  // namespace

void write_positions(const std::string& path, const Points& V) {
  write_atomically(
      path,
      [&](std::ostream& o) {
        const std::int64_t rows = V.rows();
        o.write(kMagic, sizeof kMagic);
        o.write(reinterpret_cast<const char*>(&rows), sizeof rows);
        o.write(reinterpret_cast<const char*>(V.data()), std::streamsize(V.size() * sizeof(double)));
      },
      true);
}

Points read_positions(const std::string& path) {
  InputFile in(path, "positions");
  char magic[sizeof kMagic] = {};
  std::int64_t rows = -1;
  if (read_full(in, magic, sizeof magic) != sizeof magic || std::memcmp(magic, kMagic, sizeof kMagic) != 0 ||
      read_full(in, reinterpret_cast<char*>(&rows), sizeof rows) != sizeof rows)
    throw InputError(fmt::format("{}: not a positions file", path));
  // The row count is checked against the file's size before anything is allocated for it.
  const std::uint64_t bytes = in.size(), header = sizeof kMagic + sizeof rows;
  if (rows < 0 || bytes < header || std::uint64_t(rows) != (bytes - header) / (3 * sizeof(double)) ||
      bytes != header + std::uint64_t(rows) * 3 * sizeof(double))
    throw InputError(fmt::format("{}: truncated positions file ({} rows declared, {} bytes)", path, rows, bytes));
  Points V(rows, 3);
  const std::size_t want = std::size_t(V.size()) * sizeof(double);
  if (read_full(in, reinterpret_cast<char*>(V.data()), want) != want)
    throw InputError(fmt::format("{}: truncated positions file (shorter than its size said)", path));
  return V;
}

}  // namespace db::harness
