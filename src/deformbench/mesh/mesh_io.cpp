#include "mesh/mesh_io.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/error.h"

namespace db {

namespace {

namespace fs = std::filesystem;

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string read_all(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw InputError("cannot open mesh file: " + path + " (is a directory)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot open mesh file: " + path);
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) throw InputError("cannot open mesh file: " + path + " (cannot determine its size)");
  std::string data(static_cast<std::size_t>(size), '\0');
  in.seekg(0, std::ios::beg);
  in.read(data.data(), size);
  if (!in) throw InputError("cannot open mesh file: " + path + " (read failed)");
  return data;
}

[[noreturn]] void fail(const std::string& path, int line, const std::string& msg) {
  throw InputError(fmt::format("{}: line {}: {}", path, line, msg));
}

// Line cursor over a text buffer; strips '\r' and, when asked, '#' comments.
class Lines {
 public:
  Lines(std::string_view text, bool hash_comments, std::size_t start = 0, int first_line = 1)
      : text_(text), pos_(start), line_(first_line - 1), hash_(hash_comments) {}

  //! Next line (possibly empty); false at end of text.
  bool next(std::string_view& out) {
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
  //! Next line holding at least one token.
  bool next_content(std::string_view& out) {
    while (next(out))
      if (out.find_first_not_of(" \t\r\f\v") != std::string_view::npos) return true;
    return false;
  }
  int line() const { return line_; }
  std::size_t pos() const { return pos_; }

 private:
  std::string_view text_;
  std::size_t pos_;
  int line_;
  bool hash_;
};

void split(std::string_view s, std::vector<std::string_view>& toks) {
  toks.clear();
  std::size_t i = 0;
  const std::size_t n = s.size();
  while (i < n) {
    while (i < n && (s[i] == ' ' || s[i] == '\t' || s[i] == '\r' || s[i] == '\f' || s[i] == '\v')) ++i;
    if (i >= n) break;
    std::size_t j = i;
    while (j < n && !(s[j] == ' ' || s[j] == '\t' || s[j] == '\r' || s[j] == '\f' || s[j] == '\v')) ++j;
    toks.push_back(s.substr(i, j - i));
    i = j;
  }
}

bool parse_double(std::string_view t, double& v) {
  if (!t.empty() && t[0] == '+') t.remove_prefix(1);
  if (t.empty()) return false;
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  return r.ec == std::errc() && r.ptr == t.data() + t.size();
}

bool parse_int(std::string_view t, long long& v) {
  if (!t.empty() && t[0] == '+') t.remove_prefix(1);
  if (t.empty()) return false;
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  return r.ec == std::errc() && r.ptr == t.data() + t.size();
}

std::string quote(std::string_view t) {
  constexpr std::size_t kMax = 40;
  return "'" + std::string(t.substr(0, kMax)) + (t.size() > kMax ? "...'" : "'");
}

Mesh assemble(const std::vector<double>& xyz, const std::vector<int>& tri, const std::string& path) {
  Mesh m;
  m.V = Eigen::Map<const Points>(xyz.data(), static_cast<Eigen::Index>(xyz.size() / 3), 3);
  m.F = Eigen::Map<const Faces>(tri.data(), static_cast<Eigen::Index>(tri.size() / 3), 3);
  m.name = fs::path(path).stem().string();
  return m;
}

void fan(const std::vector<long long>& poly, std::vector<int>& tri) {
  for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
    tri.push_back(static_cast<int>(poly[0]));
    tri.push_back(static_cast<int>(poly[k]));
    tri.push_back(static_cast<int>(poly[k + 1]));
  }
}

// ---------------------------------------------------------------- OFF
Mesh read_off(const std::string& path, const std::string& data) {
  Lines lines(data, true);
  std::vector<std::string_view> t;
  std::string_view line;
  if (!lines.next_content(line)) fail(path, lines.line(), "empty file (expected an OFF header)");
  split(line, t);

  // Header keyword [ST][C][N][4][n]OFF is optional; colours, normals and texture coordinates are skipped.
  bool has_c = false;
  int extra = 0;  // fixed number of per-vertex values after xyz besides the colour
  std::size_t first = 0;
  const std::string head(t[0]);
  if (!head.empty() && std::isalpha(static_cast<unsigned char>(head[0]))) {
    if (head.size() < 3 || head.compare(head.size() - 3, 3, "OFF") != 0)
      fail(path, lines.line(), "expected an OFF header, got " + quote(t[0]));
    std::string_view pre(head.data(), head.size() - 3);
    if (pre.substr(0, 2) == "ST") extra += 2, pre.remove_prefix(2);
    if (pre.substr(0, 1) == "C") has_c = true, pre.remove_prefix(1);
    if (pre.substr(0, 1) == "N") extra += 3, pre.remove_prefix(1);
    if (!pre.empty())
      fail(path, lines.line(), "unsupported OFF variant " + quote(t[0]) + " (only 3D [ST][C][N]OFF is read)");
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
  if (t.size() - first == 3 && !parse_int(t[first + 2], ne)) fail(path, count_line, "bad edge count " + quote(t[first + 2]));
  if (nv > INT32_MAX / 4 || nf > INT32_MAX / 4) fail(path, count_line, "counts too large");

  std::vector<double> xyz;
  xyz.reserve(3 * static_cast<std::size_t>(nv));
  for (long long i = 0; i < nv; ++i) {
    if (!lines.next_content(line))
      fail(path, lines.line(), fmt::format("file ends after {} of {} vertices", i, nv));
    split(line, t);
    const std::size_t lo = 3 + extra + (has_c ? 1 : 0), hi = 3 + extra + (has_c ? 4 : 0);
    if (t.size() < lo || t.size() > hi)
      fail(path, lines.line(),
           lo == hi ? fmt::format("vertex {}: expected {} values, got {}", i, lo, t.size())
                    : fmt::format("vertex {}: expected {} to {} values, got {}", i, lo, hi, t.size()));
    for (std::size_t k = 0; k < t.size(); ++k) {
      double v;
      if (!parse_double(t[k], v)) fail(path, lines.line(), fmt::format("vertex {}: bad number {}", i, quote(t[k])));
      if (k < 3) xyz.push_back(v);
    }
  }

  std::vector<int> tri;
  tri.reserve(3 * static_cast<std::size_t>(nf));
  std::vector<long long> poly;
  for (long long i = 0; i < nf; ++i) {
    if (!lines.next_content(line))
      fail(path, lines.line(), fmt::format("file ends after {} of {} faces", i, nf));
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
  }
  if (lines.next_content(line))
    fail(path, lines.line(), fmt::format("unexpected content after {} vertices and {} faces", nv, nf));
  return assemble(xyz, tri, path);
}

// ---------------------------------------------------------------- PLY
enum class PType { I8, U8, I16, U16, I32, U32, F32, F64 };

bool ply_type(std::string_view s, PType& t) {
  static const std::pair<const char*, PType> names[] = {
      {"char", PType::I8},    {"int8", PType::I8},     {"uchar", PType::U8},   {"uint8", PType::U8},
      {"short", PType::I16},  {"int16", PType::I16},   {"ushort", PType::U16}, {"uint16", PType::U16},
      {"int", PType::I32},    {"int32", PType::I32},   {"uint", PType::U32},   {"uint32", PType::U32},
      {"float", PType::F32},  {"float32", PType::F32}, {"double", PType::F64}, {"float64", PType::F64}};
  for (const auto& [n, ty] : names)
    if (s == n) {
      t = ty;
      return true;
    }
  return false;
}

bool is_integer(PType t) { return t != PType::F32 && t != PType::F64; }

std::size_t type_size(PType t) {
  switch (t) {
    case PType::I8: case PType::U8: return 1;
    case PType::I16: case PType::U16: return 2;
    case PType::I32: case PType::U32: case PType::F32: return 4;
    case PType::F64: return 8;
  }
  return 0;
}

struct Prop {
  std::string name;
  bool is_list = false;
  PType count_type = PType::U8, type = PType::F32;
};

struct Element {
  std::string name;
  long long count = 0;
  std::vector<Prop> props;
};

template <class T>
T load(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

// Reads one binary little-endian scalar as double (the host is little-endian: checked in read_ply).
double binary_value(const char* p, PType t) {
  switch (t) {
    case PType::I8: return load<std::int8_t>(p);
    case PType::U8: return load<std::uint8_t>(p);
    case PType::I16: return load<std::int16_t>(p);
    case PType::U16: return load<std::uint16_t>(p);
    case PType::I32: return load<std::int32_t>(p);
    case PType::U32: return load<std::uint32_t>(p);
    case PType::F32: return load<float>(p);
    case PType::F64: return load<double>(p);
  }
  return 0;
}

Mesh read_ply(const std::string& path, const std::string& data) {
  Lines lines(data, false);
  std::string_view line;
  std::vector<std::string_view> t;
  if (!lines.next(line) || line != "ply") fail(path, 1, "not a PLY file (first line must be 'ply')");

  bool binary = false, have_format = false, ended = false;
  std::vector<Element> elems;
  while (lines.next(line)) {
    split(line, t);
    if (t.empty()) continue;
    const int ln = lines.line();
    if (t[0] == "comment" || t[0] == "obj_info") continue;
    if (t[0] == "end_header") {
      ended = true;
      break;
    }
    if (t[0] == "format") {
      if (t.size() != 3) fail(path, ln, "expected 'format <type> 1.0'");
      if (t[1] == "ascii") binary = false;
      else if (t[1] == "binary_little_endian") binary = true;
      else if (t[1] == "binary_big_endian") fail(path, ln, "binary_big_endian PLY is not supported");
      else fail(path, ln, "unknown PLY format " + quote(t[1]));
      if (t[2] != "1.0") fail(path, ln, "unsupported PLY version " + quote(t[2]));
      have_format = true;
    } else if (t[0] == "element") {
      long long n = 0;
      if (t.size() != 3 || !parse_int(t[2], n) || n < 0) fail(path, ln, "expected 'element <name> <count>'");
      elems.push_back({std::string(t[1]), n, {}});
    } else if (t[0] == "property") {
      if (elems.empty()) fail(path, ln, "property before any element");
      Prop p;
      if (t.size() == 5 && t[1] == "list") {
        p.is_list = true;
        if (!ply_type(t[2], p.count_type) || !is_integer(p.count_type))
          fail(path, ln, "bad list count type " + quote(t[2]));
        if (!ply_type(t[3], p.type)) fail(path, ln, "unknown property type " + quote(t[3]));
        p.name = std::string(t[4]);
      } else if (t.size() == 3) {
        if (!ply_type(t[1], p.type)) fail(path, ln, "unknown property type " + quote(t[1]));
        p.name = std::string(t[2]);
      } else {
        fail(path, ln, "expected 'property <type> <name>' or 'property list <type> <type> <name>'");
      }
      elems.back().props.push_back(p);
    } else {
      fail(path, ln, "unknown header keyword " + quote(t[0]));
    }
  }
  if (!ended) fail(path, lines.line(), "header has no end_header");
  if (!have_format) fail(path, lines.line(), "header has no format line");

  // Locate the vertex coordinates and the face index list.
  int vi = -1, fi = -1, xyz_idx[3] = {-1, -1, -1}, list_idx = -1;
  for (std::size_t e = 0; e < elems.size(); ++e) {
    if (elems[e].name == "vertex") vi = static_cast<int>(e);
    if (elems[e].name == "face") fi = static_cast<int>(e);
  }
  if (vi < 0) fail(path, lines.line(), "no 'vertex' element");
  if (fi < 0) fail(path, lines.line(), "no 'face' element");
  for (std::size_t k = 0; k < elems[vi].props.size(); ++k) {
    const Prop& p = elems[vi].props[k];
    for (int c = 0; c < 3; ++c)
      if (p.name == std::string(1, static_cast<char>('x' + c))) {
        if (p.is_list) fail(path, lines.line(), "vertex property " + p.name + " is a list");
        xyz_idx[c] = static_cast<int>(k);
      }
  }
  for (int c = 0; c < 3; ++c)
    if (xyz_idx[c] < 0) fail(path, lines.line(), fmt::format("vertex element has no '{}' property", char('x' + c)));
  for (std::size_t k = 0; k < elems[fi].props.size(); ++k) {
    const Prop& p = elems[fi].props[k];
    if (p.name == "vertex_indices" || p.name == "vertex_index") {
      if (!p.is_list || !is_integer(p.type)) fail(path, lines.line(), "face " + p.name + " must be an integer list");
      list_idx = static_cast<int>(k);
    }
  }
  if (list_idx < 0) fail(path, lines.line(), "face element has no 'vertex_indices' list");

  const long long nv = elems[vi].count;
  if (nv > INT32_MAX / 4 || elems[fi].count > INT32_MAX / 4) fail(path, lines.line(), "counts too large");
  std::vector<double> xyz;
  xyz.reserve(3 * static_cast<std::size_t>(nv));
  std::vector<int> tri;
  tri.reserve(3 * static_cast<std::size_t>(elems[fi].count));
  std::vector<long long> poly;

  auto add_face = [&](long long i, auto&& where) {
    if (poly.size() < 3) fail(path, where(), fmt::format("face {}: {} corners (need at least 3)", i, poly.size()));
    for (long long v : poly)
      if (v < 0 || v >= nv) fail(path, where(), fmt::format("face {}: index {} out of range [0, {})", i, v, nv));
    fan(poly, tri);
  };

  if (!binary) {
    for (std::size_t e = 0; e < elems.size(); ++e) {
      const Element& el = elems[e];
      for (long long i = 0; i < el.count; ++i) {
        if (!lines.next_content(line))
          fail(path, lines.line(), fmt::format("file ends after {} of {} '{}' elements", i, el.count, el.name));
        const int ln = lines.line();
        split(line, t);
        std::size_t k = 0;
        double p3[3] = {0, 0, 0};
        auto token = [&](PType ty, double& v) {
          if (k >= t.size()) fail(path, ln, fmt::format("{} {}: too few values", el.name, i));
          bool ok;
          if (is_integer(ty)) {
            long long n;
            ok = parse_int(t[k], n);
            v = static_cast<double>(n);
          } else {
            ok = parse_double(t[k], v);
          }
          if (!ok) fail(path, ln, fmt::format("{} {}: bad value {}", el.name, i, quote(t[k])));
          ++k;
        };
        for (std::size_t pi = 0; pi < el.props.size(); ++pi) {
          const Prop& p = el.props[pi];
          double v;
          if (!p.is_list) {
            token(p.type, v);
            if (static_cast<int>(e) == vi)
              for (int c = 0; c < 3; ++c)
                if (xyz_idx[c] == static_cast<int>(pi)) p3[c] = v;
            continue;
          }
          double cnt;
          token(p.count_type, cnt);
          if (cnt < 0) fail(path, ln, fmt::format("{} {}: negative list length", el.name, i));
          const bool is_face_list = static_cast<int>(e) == fi && static_cast<int>(pi) == list_idx;
          if (is_face_list) poly.clear();
          for (long long j = 0; j < static_cast<long long>(cnt); ++j) {
            token(p.type, v);
            if (is_face_list) poly.push_back(static_cast<long long>(v));
          }
          if (is_face_list) add_face(i, [ln] { return ln; });
        }
        if (k != t.size()) fail(path, ln, fmt::format("{} {}: {} values too many", el.name, i, t.size() - k));
        if (static_cast<int>(e) == vi) xyz.insert(xyz.end(), p3, p3 + 3);
      }
    }
    if (lines.next_content(line)) fail(path, lines.line(), "unexpected content after the last element");
  } else {
    {
      const std::uint16_t probe = 1;
      unsigned char b;
      std::memcpy(&b, &probe, 1);
      if (b != 1) throw InputError(path + ": binary PLY needs a little-endian host");
    }
    const char* p = data.data() + lines.pos();
    const char* end = data.data() + data.size();
    if (lines.pos() > data.size()) p = end;
    const int header_lines = lines.line();
    // Binary errors name the element instead of a line; "line" reports where the header ended.
    auto where = [&] { return header_lines; };
    for (std::size_t e = 0; e < elems.size(); ++e) {
      const Element& el = elems[e];
      for (long long i = 0; i < el.count; ++i) {
        double p3[3] = {0, 0, 0};
        for (std::size_t pi = 0; pi < el.props.size(); ++pi) {
          const Prop& pr = el.props[pi];
          auto need = [&](std::size_t bytes) {
            if (static_cast<std::size_t>(end - p) < bytes)
              fail(path, where(),
                   fmt::format("binary data ends inside '{}' element {} of {}", el.name, i, el.count));
          };
          if (!pr.is_list) {
            need(type_size(pr.type));
            const double v = binary_value(p, pr.type);
            p += type_size(pr.type);
            if (static_cast<int>(e) == vi)
              for (int c = 0; c < 3; ++c)
                if (xyz_idx[c] == static_cast<int>(pi)) p3[c] = v;
            continue;
          }
          need(type_size(pr.count_type));
          const double cnt = binary_value(p, pr.count_type);
          p += type_size(pr.count_type);
          if (cnt < 0) fail(path, where(), fmt::format("'{}' element {}: negative list length", el.name, i));
          const std::size_t n = static_cast<std::size_t>(cnt);
          need(n * type_size(pr.type));
          if (static_cast<int>(e) == fi && static_cast<int>(pi) == list_idx) {
            poly.resize(n);
            for (std::size_t j = 0; j < n; ++j) poly[j] = static_cast<long long>(binary_value(p + j * type_size(pr.type), pr.type));
            add_face(i, where);
          }
          p += n * type_size(pr.type);
        }
        if (static_cast<int>(e) == vi) xyz.insert(xyz.end(), p3, p3 + 3);
      }
    }
    if (p != end) fail(path, where(), fmt::format("{} bytes of trailing data after the last element", end - p));
  }
  return assemble(xyz, tri, path);
}

// ---------------------------------------------------------------- OBJ
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
        fail(path, ln, fmt::format("vertex: expected 3 coordinates (optionally w or r g b), got {} values", t.size() - 1));
      for (std::size_t k = 1; k < t.size(); ++k) {
        double v;
        if (!parse_double(t[k], v)) fail(path, ln, "vertex: bad number " + quote(t[k]));
        if (k <= 3) xyz.push_back(v);
      }
    } else if (t[0] == "f") {
      if (t.size() < 4) fail(path, ln, fmt::format("face: {} corners (need at least 3)", t.size() - 1));
      const long long defined = static_cast<long long>(xyz.size() / 3);
      poly.clear();
      for (std::size_t k = 1; k < t.size(); ++k) {
        // a, a/b, a//c, a/b/c: only the position index a matters.
        const std::string_view tok = t[k];
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
        const long long v = idx > 0 ? idx - 1 : defined + idx;
        if (v < 0 || v >= defined)
          fail(path, ln, fmt::format("face: index {} out of range ({} vertices defined so far)", idx, defined));
        poly.push_back(v);
      }
      fan(poly, tri);
    } else if (std::find(std::begin(ignored), std::end(ignored), t[0]) == std::end(ignored)) {
      fail(path, ln, "unknown statement " + quote(t[0]));
    }
    if (xyz.size() / 3 > INT32_MAX / 4) fail(path, ln, "too many vertices");
  }
  return assemble(xyz, tri, path);
}

// ---------------------------------------------------------------- writers
// Buffered text output: fmt formats doubles as the shortest string that reads back exactly, which makes the
// text round trip lossless and the bytes deterministic.
class TextOut {
 public:
  explicit TextOut(std::ostream& os) : os_(os) {}
  ~TextOut() { flush(); }
  template <class... A>
  void put(fmt::format_string<A...> f, A&&... a) {
    fmt::format_to(std::back_inserter(buf_), f, std::forward<A>(a)...);
    if (buf_.size() > (1u << 20)) flush();
  }
  void flush() {
    os_.write(buf_.data(), static_cast<std::streamsize>(buf_.size()));
    buf_.clear();
  }

 private:
  std::ostream& os_;
  fmt::memory_buffer buf_;
};

void write_off(std::ostream& os, const Mesh& m) {
  TextOut out(os);
  out.put("OFF\n{} {} 0\n", m.num_vertices(), m.num_faces());
  for (int i = 0; i < m.num_vertices(); ++i) out.put("{} {} {}\n", m.V(i, 0), m.V(i, 1), m.V(i, 2));
  for (int f = 0; f < m.num_faces(); ++f) out.put("3 {} {} {}\n", m.F(f, 0), m.F(f, 1), m.F(f, 2));
}

void write_obj(std::ostream& os, const Mesh& m) {
  TextOut out(os);
  for (int i = 0; i < m.num_vertices(); ++i) out.put("v {} {} {}\n", m.V(i, 0), m.V(i, 1), m.V(i, 2));
  for (int f = 0; f < m.num_faces(); ++f) out.put("f {} {} {}\n", m.F(f, 0) + 1, m.F(f, 1) + 1, m.F(f, 2) + 1);
}

void write_ply(std::ostream& os, const Mesh& m) {
  const std::string header = fmt::format(
      "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty double x\nproperty double y\n"
      "property double z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
      m.num_vertices(), m.num_faces());
  os.write(header.data(), static_cast<std::streamsize>(header.size()));
  // Points is row-major: its storage is already x y z per vertex.
  os.write(reinterpret_cast<const char*>(m.V.data()), static_cast<std::streamsize>(m.V.size() * sizeof(double)));
  std::vector<char> buf;
  constexpr std::size_t kRec = 1 + 3 * sizeof(std::int32_t);
  const int chunk = 1 << 16;
  for (int f0 = 0; f0 < m.num_faces(); f0 += chunk) {
    const int f1 = std::min(m.num_faces(), f0 + chunk);
    buf.resize(static_cast<std::size_t>(f1 - f0) * kRec);
    char* p = buf.data();
    for (int f = f0; f < f1; ++f, p += kRec) {
      p[0] = 3;
      const std::int32_t idx[3] = {m.F(f, 0), m.F(f, 1), m.F(f, 2)};
      std::memcpy(p + 1, idx, sizeof(idx));
    }
    os.write(buf.data(), static_cast<std::streamsize>(buf.size()));
  }
}

}  // namespace

Mesh read_mesh(const std::string& path) {
  const std::string ext = lower(fs::path(path).extension().string());
  if (ext != ".off" && ext != ".ply" && ext != ".obj")
    throw InputError(path + ": unknown mesh extension '" + ext + "' (expected .off, .ply or .obj)");
  const std::string data = read_all(path);
  if (ext == ".off") return read_off(path, data);
  if (ext == ".ply") return read_ply(path, data);
  return read_obj(path, data);
}

void write_mesh(const std::string& path, const Mesh& mesh) {
  const std::string ext = lower(fs::path(path).extension().string());
  if (ext == ".off") write_atomically(path, [&](std::ostream& os) { write_off(os, mesh); });
  else if (ext == ".obj") write_atomically(path, [&](std::ostream& os) { write_obj(os, mesh); });
  else if (ext == ".ply") write_atomically(path, [&](std::ostream& os) { write_ply(os, mesh); }, true);
  else throw InputError(path + ": unknown mesh extension '" + ext + "' (expected .off, .ply or .obj)");
}

}  // namespace db
