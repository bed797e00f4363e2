#include "solvers/ordering/ordering_cache.h"

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include <fmt/format.h>

#include "solvers/base/atomic_file.h"
#include "solvers/base/error.h"

namespace db {
namespace {

constexpr char kMagic[8] = {'D', 'B', 'O', 'R', 'D', 'E', 'R', '1'};

//! FNV-1a, 64 bits, continued from h over `bytes` bytes.
std::uint64_t fnv1a(std::uint64_t h, const void* data, std::size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 0x100000001b3ull;
  return h;
}

bool is_permutation(const std::vector<int>& perm) {
  std::vector<char> seen(perm.size(), 0);
  for (int v : perm)
    if (v < 0 || std::size_t(v) >= perm.size() || seen[std::size_t(v)]++) return false;
  return true;
}

}  // namespace

OrderingCache OrderingCache::from_environment() {
  const char* dir = std::getenv("DEFORMBENCH_ORDERING_CACHE");
  return OrderingCache(dir ? dir : "");
}

std::string OrderingCache::path(const GraphPattern& g, const std::string& method) const {
  std::uint64_t h = fnv1a(0xcbf29ce484222325ull, method.data(), method.size());
  h = fnv1a(h, &g.n, sizeof g.n);
  if (g.n > 0) {
    h = fnv1a(h, g.colptr, (std::size_t(g.n) + 1) * sizeof(int));
    h = fnv1a(h, g.rows, std::size_t(g.colptr[g.n]) * sizeof(int));
  }
  return fmt::format("{}/{}-{}-{:016x}.perm", dir_, method, g.n, h);
}

std::vector<int> OrderingCache::find(const GraphPattern& g, const std::string& method) const {
  if (!enabled() || g.n <= 0) return {};
  std::ifstream in(path(g, method), std::ios::binary);
  char magic[sizeof kMagic];
  std::int64_t n = -1;
  if (!in.read(magic, sizeof magic) || std::memcmp(magic, kMagic, sizeof magic) != 0 ||
      !in.read(reinterpret_cast<char*>(&n), sizeof n) || n != g.n)
    return {};
  std::vector<int> perm(std::size_t(g.n));
  if (!in.read(reinterpret_cast<char*>(perm.data()), std::streamsize(perm.size() * sizeof(int))) ||
      in.peek() != std::char_traits<char>::eof() || !is_permutation(perm))
    return {};
  return perm;
}

void OrderingCache::store(const GraphPattern& g, const std::string& method, const int* perm) const {
  if (!enabled() || g.n <= 0) return;
  const std::int64_t n = g.n;
  try {
    write_atomically(
        path(g, method),
        [&](std::ostream& out) {
          out.write(kMagic, sizeof kMagic);
          out.write(reinterpret_cast<const char*>(&n), sizeof n);
          out.write(reinterpret_cast<const char*>(perm), std::streamsize(std::size_t(n) * sizeof(int)));
        },
        true);
  } catch (const Error& e) {
    throw Error(fmt::format("DEFORMBENCH_ORDERING_CACHE={}: cannot store an ordering: {}", dir_, e.what()));
  }
}

}  // namespace db
