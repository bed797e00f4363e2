#include "mesh/io/stl.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <string_view>
#include <unordered_map>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "solvers/base/error.h"
#include "core/input_file.h"
#include "mesh/io/common.h"

namespace db::io {

namespace {

constexpr std::size_t kHeaderBytes = 84;  // 80 bytes of header, the uint32 triangle count
constexpr std::size_t kRecordBytes = 50;  // normal, three corners (12 floats), a 2-byte attribute

// Three corners of one triangle, x y z each.
using Corners = std::array<std::array<double, 3>, 3>;

// Why a triangle cannot be read (or written, since the writer refuses what the reader would refuse): a non-finite
// coordinate, or two corners at the same point (welding would give the face a repeated index). `corner` is the
// corner to blame (-1: none).
struct Refusal {
  int corner = -1;
  std::string why;
};

Refusal check_triangle(const Corners& c) {
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      if (!std::isfinite(c[k][j])) return {k, fmt::format("corner {}: non-finite coordinate {}", k, c[k][j])};
  static const int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (const auto& [a, b] : pairs)
    if (std::memcmp(c[a].data(), c[b].data(), sizeof(c[a])) == 0)
      return {b, fmt::format("corners {} and {} are the same point ({}, {}, {}): a degenerate triangle", a, b,
                             c[a][0], c[a][1], c[a][2])};
  return {};
}

// Corners with bitwise-equal coordinates become one vertex, numbered in order of first appearance; faces keep
// their order.
class Welder {
 public:
  explicit Welder(std::size_t triangles_hint) {
    index_.reserve(triangles_hint);  // a closed triangle mesh has about half as many vertices as faces
    tri_.reserve(3 * triangles_hint);
  }
  //! Adds a triangle that passed check_triangle. \return false when the vertex or face count would exceed
  //! kMaxElements.
  bool add(const Corners& c) {
    for (const auto& p : c) {
      Key k;
      std::memcpy(k.data(), p.data(), sizeof(k));
      const auto [it, added] = index_.try_emplace(k, static_cast<int>(xyz_.size() / 3));
      if (added) xyz_.insert(xyz_.end(), p.begin(), p.end());
      tri_.push_back(it->second);
    }
    const auto most = static_cast<std::size_t>(kMaxElements);
    return xyz_.size() / 3 <= most && tri_.size() / 3 <= most;
  }
  std::size_t triangles() const { return tri_.size() / 3; }
  Mesh mesh(const std::string& path) const { return assemble(xyz_, tri_, path); }

 private:
  using Key = std::array<std::uint64_t, 3>;  // the coordinates' bit patterns
  struct Hash {
    std::size_t operator()(const Key& k) const {
      std::uint64_t h = 0x9e3779b97f4a7c15ull;
      for (std::uint64_t x : k) {  // splitmix64 steps
        h ^= x + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
        h = (h ^ (h >> 30)) * 0xbf58476d1ce4e5b9ull;
        h = (h ^ (h >> 27)) * 0x94d049bb133111ebull;
      }
      return static_cast<std::size_t>(h ^ (h >> 31));
    }
  };
  std::unordered_map<Key, int, Hash> index_;
  std::vector<double> xyz_;
  std::vector<int> tri_;
};

[[noreturn]] void too_many(const std::string& where) {
  throw InputError(fmt::format("{}: more than {} vertices or triangles", where, kMaxElements));
}

// ---------------------------------------------------------------- detection
std::uint32_t declared_triangles(const std::string& head) { return load<std::uint32_t>(head.data() + 80); }

std::uint64_t binary_size(std::uint32_t n) { return kHeaderBytes + kRecordBytes * static_cast<std::uint64_t>(n); }

// Whether token t is keyword k (k in lower case, t in any case).
bool is_keyword(std::string_view t, std::string_view k) {
  if (t.size() != k.size()) return false;
  for (std::size_t i = 0; i < k.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(t[i])) != k[i]) return false;
  return true;
}

// ASCII STL begins with the keyword "solid" (after blanks; any case), then a blank or the end of the line.
bool begins_with_solid(std::string_view head) {
  const std::size_t b = head.find_first_not_of(" \t\r\n\f\v");
  if (b == std::string_view::npos || head.size() - b < 5 || !is_keyword(head.substr(b, 5), "solid")) return false;
  return head.size() == b + 5 || std::string_view(" \t\r\n\f\v").find(head[b + 5]) != std::string_view::npos;
}

// What the header's count implies, for messages about a size that does not match it.
std::string size_disagreement(std::uint32_t n, std::uint64_t size) {
  return fmt::format("the binary header declares {} triangles, which take 84 + 50 * {} = {} bytes, but the file has "
                     "{} bytes (a truncated file or a wrong count)",
                     n, n, binary_size(n), size);
}

// ---------------------------------------------------------------- binary
Mesh read_binary(const std::string& path, const std::string& data) {
  require_little_endian_host(path, "binary STL");
  const std::uint32_t n = declared_triangles(data);
  if (data.size() != binary_size(n))  // the file changed between the size check and the read
    throw InputError(fmt::format("{}: {}", path, size_disagreement(n, data.size())));
  if (n == 0) throw InputError(path + ": binary STL with 0 triangles (an empty mesh)");
  if (n > kMaxElements)
    throw InputError(fmt::format("{}: binary STL declares {} triangles (at most {})", path, n, kMaxElements));
  Welder welder(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::size_t at = kHeaderBytes + kRecordBytes * i;
    const char* corners = data.data() + at + 12;  // after the normal
    Corners c;
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j) c[k][j] = load<float>(corners + 4 * (3 * k + j));
    auto where = [&] { return fmt::format("{}: triangle {} (byte {})", path, i, at); };
    if (const Refusal r = check_triangle(c); r.corner >= 0) throw InputError(where() + ": " + r.why);
    if (!welder.add(c)) too_many(where());
  }
  return welder.mesh(path);
}

// ---------------------------------------------------------------- ASCII
// Statements of an ASCII STL, one a line.
class StlText {
 public:
  StlText(const std::string& path, const std::string& data, std::string binary_hint)
      : path_(path), lines_(data, false), hint_(std::move(binary_hint)) {}

  //! Moves to the next statement; false at the end of the file.
  bool next() {
    std::string_view line;
    if (!lines_.next_content(line)) return false;
    if (line.find('\0') != std::string_view::npos) fail(path_, lines_.line(), "binary data in an ASCII STL" + hint_);
    line_ = line;
    split(line, t_);
    return true;
  }
  //! Moves to the next statement of facet i, which must exist. \throw InputError "file ends inside facet i".
  void next_in(std::size_t i, const char* form) {
    if (!next()) fail(path_, lines_.line(), fmt::format("file ends inside facet {} (expected '{}')", i, form));
  }
  //! Whether the statement's first token is keyword `k` (lower case; the file's may be any case).
  bool is(std::string_view k) const { return is_keyword(t_[0], k); }
  //! The statement must be the keywords `words` followed by `n` numbers, read into out.
  void expect(std::initializer_list<std::string_view> words, std::size_t n = 0, double* out = nullptr) {
    auto shape = [&] { return fmt::format("{}{}", fmt::join(words, " "), n == 3 ? " x y z" : ""); };
    bool ok = t_.size() == words.size() + n;
    for (std::size_t k = 0; ok && k < words.size(); ++k) ok = is_keyword(t_[k], words.begin()[k]);
    if (!ok) fail(path_, line(), fmt::format("expected '{}', got {}", shape(), quote(line_)));
    for (std::size_t k = 0; k < n; ++k)
      if (!parse_double(t_[words.size() + k], out[k]))
        fail(path_, line(), fmt::format("bad number {} in '{}'", quote(t_[words.size() + k]), shape()));
  }
  int line() const { return lines_.line(); }
  std::string_view text() const { return line_; }

 private:
  const std::string& path_;
  Lines lines_;
  std::string hint_;
  std::string_view line_;
  std::vector<std::string_view> t_;
};

// facet normal nx ny nz / outer loop / vertex x y z (3 times) / endloop / endfacet, the first line read already.
void read_facet(StlText& in, const std::string& path, std::size_t i, Welder& welder) {
  double normal[3];
  in.expect({"facet", "normal"}, 3, normal);  // read past: see stl.h
  in.next_in(i, "outer loop");
  in.expect({"outer", "loop"});
  Corners c;
  int line[3];
  for (int k = 0; k < 3; ++k) {
    in.next_in(i, "vertex x y z");
    if (k > 0 && in.is("endloop")) fail(path, in.line(), fmt::format("facet {}: {} corners (a facet has 3)", i, k));
    in.expect({"vertex"}, 3, c[k].data());
    line[k] = in.line();
  }
  in.next_in(i, "endloop");
  if (in.is("vertex")) fail(path, in.line(), fmt::format("facet {}: more than 3 corners (a facet has 3)", i));
  in.expect({"endloop"});
  in.next_in(i, "endfacet");
  in.expect({"endfacet"});
  if (const Refusal r = check_triangle(c); r.corner >= 0)
    fail(path, line[r.corner], fmt::format("facet {}: {}", i, r.why));
  if (!welder.add(c)) too_many(fmt::format("{}: line {}", path, in.line()));
}

// solid NAME, facets, endsolid [NAME]; several solids are read one after the other.
Mesh read_ascii(const std::string& path, const std::string& data, std::string binary_hint) {
  StlText in(path, data, std::move(binary_hint));
  Welder welder(0);
  bool inside = false;
  while (in.next()) {
    if (!inside) {
      if (!in.is("solid")) fail(path, in.line(), "expected 'solid NAME', got " + quote(in.text()));
      inside = true;
    } else if (in.is("endsolid")) {
      inside = false;
    } else if (in.is("facet")) {
      read_facet(in, path, welder.triangles(), welder);
    } else {
      fail(path, in.line(), "expected 'facet normal nx ny nz' or 'endsolid', got " + quote(in.text()));
    }
  }
  if (inside)
    fail(path, in.line(), fmt::format("file ends after {} facets without 'endsolid' (a truncated file?)",
                                      welder.triangles()));
  if (welder.triangles() == 0) fail(path, in.line(), "no facets (an empty mesh)");
  return welder.mesh(path);
}

// ---------------------------------------------------------------- writing
// The corners of face f as the file will hold them: doubles (ASCII), or rounded to floats (binary; in range,
// check_stl_writable made sure). The rounding is a pass of its own: written as a conditional inside the copy loop,
// g++ 12.2 -O3 (its SLP vectorizer) lost it for some corners, and the writer's check then missed a triangle that
// rounding collapses (StlWriterRefusesWhatItsReaderWouldRefuse catches it).
Corners corners_as_written(const Mesh& m, int f, StlEncoding e) {
  Corners c;
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j) c[k][j] = m.V(m.F(f, k), j);
  if (e == StlEncoding::Binary)
    for (auto& p : c)
      for (double& x : p) x = static_cast<float>(x);
  return c;
}

// Unit normal (b - a) x (c - a), scaled by its largest component first so that squaring cannot overflow;
// 0 0 0 for a zero or non-finite cross product.
std::array<double, 3> unit_normal(const Corners& c) {
  double u[3], v[3];
  for (int j = 0; j < 3; ++j) u[j] = c[1][j] - c[0][j], v[j] = c[2][j] - c[0][j];
  std::array<double, 3> n = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  const double big = std::max({std::abs(n[0]), std::abs(n[1]), std::abs(n[2])});
  if (!(big > 0) || !std::isfinite(big)) return {0, 0, 0};
  for (double& x : n) x /= big;
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (double& x : n) x /= len;
  return n;
}

// mesh.name on one line of printable ASCII.
std::string solid_name(const std::string& name) {
  std::string s = name;
  for (char& ch : s)
    if (static_cast<unsigned char>(ch) < 0x20 || static_cast<unsigned char>(ch) >= 0x7f) ch = '_';
  return s.empty() ? "mesh" : s;
}

void write_ascii(std::ostream& os, const Mesh& m) {
  TextOut out(os);
  const std::string name = solid_name(m.name);
  out.put("solid {}\n", name);
  for (int f = 0; f < m.num_faces(); ++f) {
    const Corners c = corners_as_written(m, f, StlEncoding::Ascii);
    const auto n = unit_normal(c);
    out.put("  facet normal {} {} {}\n    outer loop\n", n[0], n[1], n[2]);
    for (const auto& p : c) out.put("      vertex {} {} {}\n", p[0], p[1], p[2]);
    out.put("    endloop\n  endfacet\n");
  }
  out.put("endsolid {}\n", name);
}

void write_binary(std::ostream& os, const Mesh& m) {
  // Not "solid ...": readers that look at the header alone would take the file for ASCII.
  char header[kHeaderBytes] = "binary STL written by deformbench";
  const auto n = static_cast<std::uint32_t>(m.num_faces());
  std::memcpy(header + 80, &n, 4);
  os.write(header, sizeof(header));
  std::vector<char> buf;
  const int chunk = 1 << 16;
  for (int f0 = 0; f0 < m.num_faces(); f0 += chunk) {
    const int f1 = std::min(m.num_faces(), f0 + chunk);
    buf.assign(static_cast<std::size_t>(f1 - f0) * kRecordBytes, '\0');  // attribute bytes 0
    char* p = buf.data();
    for (int f = f0; f < f1; ++f, p += kRecordBytes) {
      const Corners c = corners_as_written(m, f, StlEncoding::Binary);
      const auto normal = unit_normal(c);
      float v[12];
      for (int j = 0; j < 3; ++j) v[j] = static_cast<float>(normal[j]);
      for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j) v[3 + 3 * k + j] = static_cast<float>(c[k][j]);
      std::memcpy(p, v, sizeof(v));
    }
    os.write(buf.data(), static_cast<std::streamsize>(buf.size()));
  }
}

}  // namespace

Mesh read_stl(const std::string& path) {
  InputFile in(path, "mesh");
  const std::uint64_t size = in.size();
  std::string head(static_cast<std::size_t>(std::min<std::uint64_t>(size, kHeaderBytes)), '\0');
  head.resize(in.read(head.data(), head.size()));
  if (head.size() == kHeaderBytes && binary_size(declared_triangles(head)) == size)
    return read_binary(path, head + in.read_all());
  if (begins_with_solid(head)) {
    const std::string hint =
        head.size() == kHeaderBytes
            ? " (or a binary STL whose header begins with 'solid', but " +
                  size_disagreement(declared_triangles(head), size) + ")"
            : "";
    return read_ascii(path, read_file(in, path, head), hint);
  }
  if (head.size() < kHeaderBytes)
    throw InputError(fmt::format("{}: {} bytes, too short for a binary STL (84 bytes at least) and not an ASCII STL "
                                 "(it does not begin with 'solid')",
                                 path, size));
  throw InputError(fmt::format("{}: not an ASCII STL (it does not begin with 'solid'), and {}", path,
                               size_disagreement(declared_triangles(head), size)));
}

void check_stl_writable(const std::string& path, const Mesh& mesh, StlEncoding encoding) {
  if (mesh.num_faces() == 0)
    throw InputError("cannot write " + path + ": STL holds triangles only, and the mesh has no face");
  try {
    check_arrays(mesh);
  } catch (const InputError& e) {
    throw InputError("cannot write " + path + ": " + e.what());
  }
  const bool binary = encoding == StlEncoding::Binary;
  if (binary)
    for (int v = 0; v < mesh.num_vertices(); ++v)
      for (int j = 0; j < 3; ++j)
        if (std::abs(mesh.V(v, j)) > FLT_MAX)
          throw InputError(fmt::format("cannot write {}: vertex {}: coordinate {} is beyond binary STL's 32-bit "
                                       "floats (ASCII STL keeps doubles)",
                                       path, v, mesh.V(v, j)));
  for (int f = 0; f < mesh.num_faces(); ++f)
    if (const Refusal r = check_triangle(corners_as_written(mesh, f, encoding)); r.corner >= 0)
      throw InputError(fmt::format("cannot write {}: face {}: {}{}; STL cannot hold it (its reader refuses one)",
                                   path, f, r.why, binary ? " once rounded to 32-bit floats" : ""));
}

void write_stl(std::ostream& os, const Mesh& mesh, StlEncoding encoding) {
  if (encoding == StlEncoding::Binary) write_binary(os, mesh);
  else write_ascii(os, mesh);
}

}  // namespace db::io
