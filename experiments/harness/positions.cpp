#include "harness/positions.h"

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "solvers/base/atomic_file.h"
#include "solvers/base/error.h"

namespace db::harness {
namespace {

constexpr char kMagic[8] = {'D', 'B', 'P', 'O', 'S', '0', '0', '1'};

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
  std::ifstream in(path, std::ios::binary);
  char magic[sizeof kMagic] = {};
  std::int64_t rows = -1;
  if (!in.read(magic, sizeof magic) || std::memcmp(magic, kMagic, sizeof kMagic) != 0 ||
      !in.read(reinterpret_cast<char*>(&rows), sizeof rows))
    throw InputError(fmt::format("{}: not a positions file", path));
  const auto bytes = std::filesystem::file_size(path);
  if (rows < 0 || bytes != sizeof kMagic + sizeof rows + std::uintmax_t(rows) * 3 * sizeof(double))
    throw InputError(fmt::format("{}: truncated positions file ({} rows declared, {} bytes)", path, rows, bytes));
  Points V(rows, 3);
  in.read(reinterpret_cast<char*>(V.data()), std::streamsize(V.size() * sizeof(double)));
  return V;
}

}  // namespace db::harness
