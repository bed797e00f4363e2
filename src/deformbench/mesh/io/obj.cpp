#include "mesh/io/obj.h"

#include <algorithm>
#include <iterator>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "mesh/io/common.h"

namespace db::io {

namespace {

// An OBJ face corner a, a/b, a//c or a/b/c: the position index a as the file writes it (1-based; negative counts
// back from the last vertex defined so far), turned into a 0-based index. Errors quote the index as written.
long long obj_corner(const std::string& path, int ln, std::string_view tok, long long defined) {
  const std::string_view a = tok.substr(0, tok.find('/'));
  long long idx;
  if (!parse_int(a, idx)) fail(path, ln, "face: bad index " + quote(tok));
  for (std::string_view rest = tok.substr(a.size()); !rest.empty();) {
    rest.remove_prefix(1);  // the '/'
    const std::string_view part = rest.substr(0, rest.find('/'));
    long long dummy;
    if (!part.empty() && !parse_int(part, dummy)) fail(path, ln, "face: bad index " + quote(tok));
    rest.remove_prefix(part.size());
  }
  if (idx == 0) fail(path, ln, "face: index 0 (OBJ indices start at 1)");
  if (idx > defined)
    fail(path, ln, fmt::format("face: index {} out of range (OBJ indices are 1-based; {} vertices defined so far)", idx,
                               defined));
  if (idx < -defined)
    fail(path, ln, fmt::format("face: index {} out of range (a negative index counts back from the last vertex; {} "
                               "vertices defined so far)",
                               idx, defined));
  return idx > 0 ? idx - 1 : defined + idx;
}

}  // namespace

Mesh read_obj(const std::string& path, const std::string& data) {
  Lines lines(data, true);
  std::string_view line;
  std::vector<std::string_view> t;
  std::vector<double> xyz;
  std::vector<int> tri;
  std::vector<long long> poly;
  // Statements that carry nothing a triangle mesh needs.
  static const char* ignored[] = {"vt", "vn", "vp", "o", "g", "s", "usemtl", "mtllib", "l", "p"};
  while (lines.next_content(line)) {
    split(line, t);
    const int ln = lines.line();
    if (t[0] == "v") {
      // x y z, optionally w or an r g b colour.
      if (t.size() != 4 && t.size() != 5 && t.size() != 7)
        fail(path, ln,
             fmt::format("vertex: expected 3 coordinates (optionally w or r g b), got {} values", t.size() - 1));
      double p[3];
      for (std::size_t k = 1; k < t.size(); ++k) {
        double v;
        if (!parse_double(t[k], v)) fail(path, ln, "vertex: bad number " + quote(t[k]));
        if (k <= 3) p[k - 1] = v;
      }
      check_coordinates(path, ln, static_cast<long long>(xyz.size() / 3) + 1, p);
      xyz.insert(xyz.end(), p, p + 3);
    } else if (t[0] == "f") {
      if (t.size() < 4) fail(path, ln, fmt::format("face: {} corners (need at least 3)", t.size() - 1));
      const long long defined = static_cast<long long>(xyz.size() / 3);
      poly.clear();
      for (std::size_t k = 1; k < t.size(); ++k) poly.push_back(obj_corner(path, ln, t[k], defined));
      fan(poly, tri);
    } else if (std::find(std::begin(ignored), std::end(ignored), t[0]) == std::end(ignored)) {
      fail(path, ln, "unknown statement " + quote(t[0]));
    }
    const auto most = static_cast<std::size_t>(kMaxElements);
    if (xyz.size() / 3 > most || tri.size() / 3 > most)
      fail(path, ln, "too many vertices or faces");
  }
  return assemble(xyz, tri, path);
}

void write_obj(std::ostream& os, const Mesh& m) {
  TextOut out(os);
  for (int i = 0; i < m.num_vertices(); ++i) out.put("v {} {} {}\n", m.V(i, 0), m.V(i, 1), m.V(i, 2));
  for (int f = 0; f < m.num_faces(); ++f) out.put("f {} {} {}\n", m.F(f, 0) + 1, m.F(f, 1) + 1, m.F(f, 2) + 1);
}

}  // namespace db::io
