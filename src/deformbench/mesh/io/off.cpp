#include "mesh/io/off.h"

#include <algorithm>
#include <cctype>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "mesh/io/common.h"

namespace db::io {

namespace {

// Vertex layout from the optional header keyword [ST][C][N]OFF: colours, normals and texture coordinates are
// skipped.
struct OffLayout {
  std::size_t min_values = 3, max_values = 3;  //!< per vertex line
};

OffLayout off_keyword(const std::string& path, int line, std::string_view head) {
  if (head.size() < 3 || head.substr(head.size() - 3) != "OFF")
    fail(path, line, "expected an OFF header, got " + quote(head));
  std::string_view pre = head.substr(0, head.size() - 3);
  OffLayout l;
  if (pre.substr(0, 2) == "ST") l.min_values += 2, l.max_values += 2, pre.remove_prefix(2);
  if (pre.substr(0, 1) == "C") l.min_values += 1, l.max_values += 4, pre.remove_prefix(1);
  if (pre.substr(0, 1) == "N") l.min_values += 3, l.max_values += 3, pre.remove_prefix(1);
  if (!pre.empty()) fail(path, line, "unsupported OFF variant " + quote(head) + " (only 3D [ST][C][N]OFF is read)");
  return l;
}

void read_off_vertices(const std::string& path, Lines& lines, long long nv, const OffLayout& l,
                       std::vector<double>& xyz) {
  std::vector<std::string_view> t;
  std::string_view line;
  for (long long i = 0; i < nv; ++i) {
    if (!lines.next_content(line)) fail(path, lines.line(), fmt::format("file ends after {} of {} vertices", i, nv));
    split(line, t);
    if (t.size() < l.min_values || t.size() > l.max_values)
      fail(path, lines.line(),
           l.min_values == l.max_values
               ? fmt::format("vertex {}: expected {} values, got {}", i, l.min_values, t.size())
               : fmt::format("vertex {}: expected {} to {} values, got {}", i, l.min_values, l.max_values, t.size()));
    double p[3];
    for (std::size_t k = 0; k < t.size(); ++k) {
      double v;
      if (!parse_double(t[k], v)) fail(path, lines.line(), fmt::format("vertex {}: bad number {}", i, quote(t[k])));
      if (k < 3) p[k] = v;
    }
    check_coordinates(path, lines.line(), i, p);
    xyz.insert(xyz.end(), p, p + 3);
  }
}

void read_off_faces(const std::string& path, Lines& lines, long long nv, long long nf, std::vector<int>& tri) {
  std::vector<std::string_view> t;
  std::string_view line;
  std::vector<long long> poly;
  for (long long i = 0; i < nf; ++i) {
    if (!lines.next_content(line)) fail(path, lines.line(), fmt::format("file ends after {} of {} faces", i, nf));
    split(line, t);
    long long n = 0;
    if (!parse_int(t[0], n)) fail(path, lines.line(), fmt::format("face {}: bad corner count {}", i, quote(t[0])));
    if (n < 3) fail(path, lines.line(), fmt::format("face {}: {} corners (need at least 3)", i, n));
    // Up to four trailing values are a face colour.
    if (t.size() < static_cast<std::size_t>(n) + 1 || t.size() > static_cast<std::size_t>(n) + 5)
      fail(path, lines.line(), fmt::format("face {}: expected {} indices, got {} values", i, n, t.size() - 1));
    poly.resize(n);
    for (long long k = 0; k < n; ++k) {
      if (!parse_int(t[k + 1], poly[k]))
        fail(path, lines.line(), fmt::format("face {}: bad index {}", i, quote(t[k + 1])));
      if (poly[k] < 0 || poly[k] >= nv)
        fail(path, lines.line(), fmt::format("face {}: index {} out of range [0, {})", i, poly[k], nv));
    }
    for (std::size_t k = n + 1; k < t.size(); ++k) {
      double c;
      if (!parse_double(t[k], c)) fail(path, lines.line(), fmt::format("face {}: bad value {}", i, quote(t[k])));
    }
    fan(poly, tri);
    if (tri.size() / 3 > static_cast<std::size_t>(kMaxElements)) fail(path, lines.line(), "too many triangles");
  }
}

}  // namespace

Mesh read_off(const std::string& path, const std::string& data) {
  Lines lines(data, true);
  std::vector<std::string_view> t;
  std::string_view line;
  if (!lines.next_content(line)) fail(path, lines.line(), "empty file (expected an OFF header)");
  split(line, t);

  OffLayout layout;
  std::size_t first = 0;
  if (std::isalpha(static_cast<unsigned char>(t[0][0]))) {
    layout = off_keyword(path, lines.line(), t[0]);
    first = 1;
    if (t.size() == 1) {
      if (!lines.next_content(line)) fail(path, lines.line(), "missing the vertex/face count line");
      split(line, t);
      first = 0;
    }
  }
  const int count_line = lines.line();
  if (t.size() - first < 2 || t.size() - first > 3)
    fail(path, count_line, "expected '#vertices #faces [#edges]'");
  long long nv = 0, nf = 0, ne = 0;
  if (!parse_int(t[first], nv) || nv < 0) fail(path, count_line, "bad vertex count " + quote(t[first]));
  if (!parse_int(t[first + 1], nf) || nf < 0) fail(path, count_line, "bad face count " + quote(t[first + 1]));
  if (t.size() - first == 3 && (!parse_int(t[first + 2], ne) || ne < 0))
    fail(path, count_line, "bad edge count " + quote(t[first + 2]));
  if (nv > kMaxElements || nf > kMaxElements)
    fail(path, count_line,
         fmt::format("counts too large ({} vertices, {} faces; at most {} each)", nv, nf, kMaxElements));
  // The last line may lack its newline: one byte of slack.
  std::size_t left = data.size() - std::min(data.size(), lines.pos()) + 1;
  check_declared(path, count_line, nv, 2 * layout.min_values, left, "the header's vertex count");
  check_declared(path, count_line, nf, 8, left, "the header's face count");  // "3 a b c\n"

  std::vector<double> xyz;
  xyz.reserve(3 * static_cast<std::size_t>(nv));
  read_off_vertices(path, lines, nv, layout, xyz);
  std::vector<int> tri;
  tri.reserve(3 * static_cast<std::size_t>(nf));
  read_off_faces(path, lines, nv, nf, tri);
  if (lines.next_content(line))
    fail(path, lines.line(), fmt::format("unexpected content after {} vertices and {} faces", nv, nf));
  return assemble(xyz, tri, path);
}

void write_off(std::ostream& os, const Mesh& m) {
  TextOut out(os);
  out.put("OFF\n{} {} 0\n", m.num_vertices(), m.num_faces());
  for (int i = 0; i < m.num_vertices(); ++i) out.put("{} {} {}\n", m.V(i, 0), m.V(i, 1), m.V(i, 2));
  for (int f = 0; f < m.num_faces(); ++f) out.put("3 {} {} {}\n", m.F(f, 0), m.F(f, 1), m.F(f, 2));
}

}  // namespace db::io
