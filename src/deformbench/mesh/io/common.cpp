#include "mesh/io/common.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>

#include "solvers/base/error.h"
#include "core/input_file.h"

namespace db::io {

std::string read_file(const std::string& path) {
  InputFile in(path, "mesh");
  return read_file(in, path, {});
}

std::string read_file(InputFile& in, const std::string& path, std::string head) {
  const std::size_t first = static_cast<std::size_t>(std::min<std::uint64_t>(in.size(), kMaxFirstLine));
  if (head.size() < first) {
    const std::size_t had = head.size();
    head.resize(first);
    head.resize(had + in.read(head.data() + had, first - had));
  }
  if (in.size() > kMaxFirstLine && head.find('\n') == std::string::npos)
    throw InputError(fmt::format("{}: line 1: longer than {} bytes (not a mesh file)", path, kMaxFirstLine));
  head += in.read_all();
  return head;
}

void fail(const std::string& path, int line, const std::string& msg) {
  throw InputError(fmt::format("{}: line {}: {}", path, line, msg));
}

bool Lines::next(std::string_view& out) {
  if (pos_ >= text_.size()) return false;
  std::size_t e = text_.find('\n', pos_);
  if (e == std::string_view::npos) e = text_.size();
  out = text_.substr(pos_, e - pos_);
  pos_ = e + 1;
  ++line_;
  if (hash_) {
    const std::size_t h = out.find('#');
    if (h != std::string_view::npos) out = out.substr(0, h);
  }
  if (!out.empty() && out.back() == '\r') out.remove_suffix(1);
  return true;
}

bool Lines::next_content(std::string_view& out) {
  while (next(out))
    if (out.find_first_not_of(" \t\r\f\v") != std::string_view::npos) return true;
  return false;
}

namespace {
bool blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }
}  // namespace

void split(std::string_view s, std::vector<std::string_view>& toks) {
  toks.clear();
  std::size_t i = 0;
  const std::size_t n = s.size();
  while (i < n) {
    while (i < n && blank(s[i])) ++i;
    if (i >= n) break;
    std::size_t j = i;
    while (j < n && !blank(s[j])) ++j;
    toks.push_back(s.substr(i, j - i));
    i = j;
  }
}

namespace {
template <class T>
bool parse_whole(std::string_view t, T& v) {
  if (!t.empty() && t[0] == '+') t.remove_prefix(1);
  if (t.empty()) return false;
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  return r.ec == std::errc() && r.ptr == t.data() + t.size();
}
}  // namespace

bool parse_double(std::string_view t, double& v) { return parse_whole(t, v); }
bool parse_int(std::string_view t, long long& v) { return parse_whole(t, v); }

std::string quote(std::string_view t) {
  constexpr std::size_t kMax = 40;
  return "'" + std::string(t.substr(0, kMax)) + (t.size() > kMax ? "...'" : "'");
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

Mesh assemble(const std::vector<double>& xyz, const std::vector<int>& tri, const std::string& path) {
  Mesh m;
  m.V = Eigen::Map<const Points>(xyz.data(), static_cast<Eigen::Index>(xyz.size() / 3), 3);
  m.F = Eigen::Map<const Faces>(tri.data(), static_cast<Eigen::Index>(tri.size() / 3), 3);
  m.name = std::filesystem::path(path).stem().string();
  return m;
}

void fan(const std::vector<long long>& poly, std::vector<int>& tri) {
  for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
    tri.push_back(static_cast<int>(poly[0]));
    tri.push_back(static_cast<int>(poly[k]));
    tri.push_back(static_cast<int>(poly[k + 1]));
  }
}

void check_declared(const std::string& path, int line, unsigned long long count, std::size_t min_bytes,
                    std::size_t& bytes_left, const std::string& what) {
  if (min_bytes == 0) {
    if (count > 0) fail(path, line, fmt::format("{} declares {} entries that hold no values", what, count));
    return;
  }
  if (count > bytes_left / min_bytes)
    fail(path, line,
         fmt::format("{} declares {} entries of at least {} bytes each, but only {} bytes of data remain (a truncated "
                     "file or a wrong count)",
                     what, count, min_bytes, bytes_left));
  bytes_left -= static_cast<std::size_t>(count) * min_bytes;
}

void check_coordinates(const std::string& path, int line, long long i, const double* p) {
  for (int c = 0; c < 3; ++c)
    if (!std::isfinite(p[c])) fail(path, line, fmt::format("vertex {}: non-finite coordinate {}", i, p[c]));
}

void require_little_endian_host(const std::string& path, const std::string& format) {
  const std::uint16_t probe = 1;
  unsigned char b;
  std::memcpy(&b, &probe, 1);
  if (b != 1) throw InputError(fmt::format("{}: {} needs a little-endian host", path, format));
}

void TextOut::flush() {
  os_.write(buf_.data(), static_cast<std::streamsize>(buf_.size()));
  buf_.clear();
}

}  // namespace db::io
