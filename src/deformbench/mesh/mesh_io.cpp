#include "mesh/mesh_io.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string_view>
#include <type_traits>
#include <vector>

#include <fmt/format.h>

#include "solvers/base/atomic_file.h"
#include "solvers/base/error.h"
#include "core/input_file.h"

namespace db {

namespace {

namespace fs = std::filesystem;

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Every format read here starts with a short text line (OFF, ply, an OBJ statement or comment).
constexpr std::size_t kMaxFirstLine = 64 << 10;

// The whole file, read only once its first line has ended within kMaxFirstLine bytes: a large file that is no
// mesh (a sparse file of zeros) is refused after those bytes, not after reading it all.
std::string read_all(const std::string& path) {
  InputFile in(path, "mesh");
  std::string data(static_cast<std::size_t>(std::min<std::uint64_t>(in.size(), kMaxFirstLine)), '\0');
  data.resize(in.read(data.data(), data.size()));
  if (in.size() > kMaxFirstLine && data.find('\n') == std::string::npos)
    throw InputError(fmt::format("{}: line 1: longer than {} bytes (not a mesh file)", path, kMaxFirstLine));
  data += in.read_all();
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

// Every count a file declares is checked against the bytes that follow before anything is allocated or looped
// over: a text value takes at least one character and one separator, a binary one its size. A header that
// declares 10^12 entries so ends at once with an error instead of a hang or an allocation failure.
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
    if (!std::isfinite(p[c]))
      fail(path, line, fmt::format("vertex {}: non-finite coordinate {}", i, p[c]));
}

// ---------------------------------------------------------------- OFF
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
  if (t.size() - first == 3 && !parse_int(t[first + 2], ne))
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

// Range of an integer type, so a text value is checked against what a binary file could hold.
std::pair<long long, long long> type_range(PType t) {
  switch (t) {
    case PType::I8: return {INT8_MIN, INT8_MAX};
    case PType::U8: return {0, UINT8_MAX};
    case PType::I16: return {INT16_MIN, INT16_MAX};
    case PType::U16: return {0, UINT16_MAX};
    case PType::I32: return {INT32_MIN, INT32_MAX};
    default: return {0, UINT32_MAX};
  }
}

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
  int line = 0;  //!< of its header line
};

struct PlyHeader {
  bool binary = false;
  std::vector<Element> elems;
  std::size_t body = 0;  //!< byte offset of the first element
  int lines = 0;         //!< header lines (binary errors report where the header ended)
};

// What the reader takes from the file: vertex coordinates, and triangles from a face list and/or triangle strips.
struct PlyLayout {
  int vertex = -1, face = -1, strips = -1;  //!< element indices
  int xyz[3] = {-1, -1, -1};                //!< property indices in the vertex element
  int face_list = -1, strip_list = -1;      //!< property indices of the index lists
};

Prop parse_ply_property(const std::string& path, int ln, const std::vector<std::string_view>& t) {
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
  return p;
}

void parse_ply_format(const std::string& path, int ln, const std::vector<std::string_view>& t, PlyHeader& h) {
  if (t.size() != 3) fail(path, ln, "expected 'format <type> 1.0'");
  if (t[1] == "ascii") h.binary = false;
  else if (t[1] == "binary_little_endian") h.binary = true;
  else if (t[1] == "binary_big_endian") fail(path, ln, "binary_big_endian PLY is not supported");
  else fail(path, ln, "unknown PLY format " + quote(t[1]));
  if (t[2] != "1.0") fail(path, ln, "unsupported PLY version " + quote(t[2]));
}

PlyHeader parse_ply_header(const std::string& path, const std::string& data) {
  Lines lines(data, false);
  std::string_view line;
  std::vector<std::string_view> t;
  if (!lines.next(line) || line != "ply") fail(path, 1, "not a PLY file (first line must be 'ply')");
  PlyHeader h;
  bool have_format = false, ended = false;
  while (!ended && lines.next(line)) {
    split(line, t);
    const int ln = lines.line();
    if (t.empty() || t[0] == "comment" || t[0] == "obj_info") continue;
    if (t[0] == "end_header") {
      ended = true;
    } else if (t[0] == "format") {
      parse_ply_format(path, ln, t, h);
      have_format = true;
    } else if (t[0] == "element") {
      long long n = 0;
      if (t.size() != 3 || !parse_int(t[2], n) || n < 0) fail(path, ln, "expected 'element <name> <count>'");
      h.elems.push_back({std::string(t[1]), n, {}, ln});
    } else if (t[0] == "property") {
      if (h.elems.empty()) fail(path, ln, "property before any element");
      h.elems.back().props.push_back(parse_ply_property(path, ln, t));
    } else {
      fail(path, ln, "unknown header keyword " + quote(t[0]));
    }
  }
  if (!ended) fail(path, lines.line(), "header has no end_header");
  if (!have_format) fail(path, lines.line(), "header has no format line");
  h.body = std::min(lines.pos(), data.size());
  h.lines = lines.line();
  return h;
}

int index_list(const std::string& path, int ln, const Element& el) {
  int idx = -1;
  for (std::size_t k = 0; k < el.props.size(); ++k) {
    const Prop& p = el.props[k];
    if (p.name == "vertex_indices" || p.name == "vertex_index") {
      if (!p.is_list || !is_integer(p.type)) fail(path, ln, el.name + " " + p.name + " must be an integer list");
      idx = static_cast<int>(k);
    }
  }
  if (idx < 0) fail(path, ln, el.name + " element has no 'vertex_indices' list");
  return idx;
}

PlyLayout locate(const std::string& path, const PlyHeader& h) {
  PlyLayout l;
  for (std::size_t e = 0; e < h.elems.size(); ++e) {
    if (h.elems[e].name == "vertex") l.vertex = static_cast<int>(e);
    if (h.elems[e].name == "face") l.face = static_cast<int>(e);
    if (h.elems[e].name == "tristrips") l.strips = static_cast<int>(e);
  }
  if (l.vertex < 0) fail(path, h.lines, "no 'vertex' element");
  if (l.face < 0 && l.strips < 0) fail(path, h.lines, "no 'face' element (nor 'tristrips' triangle strips)");
  const Element& v = h.elems[l.vertex];
  for (std::size_t k = 0; k < v.props.size(); ++k)
    for (int c = 0; c < 3; ++c)
      if (v.props[k].name == std::string(1, static_cast<char>('x' + c))) {
        if (v.props[k].is_list) fail(path, v.line, "vertex property " + v.props[k].name + " is a list");
        l.xyz[c] = static_cast<int>(k);
      }
  for (int c = 0; c < 3; ++c)
    if (l.xyz[c] < 0) fail(path, v.line, fmt::format("vertex element has no '{}' property", char('x' + c)));
  if (l.face >= 0) l.face_list = index_list(path, h.elems[l.face].line, h.elems[l.face]);
  if (l.strips >= 0) l.strip_list = index_list(path, h.elems[l.strips].line, h.elems[l.strips]);
  return l;
}

// Least bytes one entry takes: binary, its scalars and list counts; ASCII, a character and a separator per value.
std::size_t min_entry_bytes(const Element& el, bool binary) {
  std::size_t n = 0;
  for (const Prop& p : el.props) n += binary ? type_size(p.is_list ? p.count_type : p.type) : 2;
  return n;
}

void check_ply_counts(const std::string& path, const PlyHeader& h, std::size_t body_bytes) {
  std::size_t left = body_bytes + (h.binary ? 0 : 1);  // a text file's last line may lack its newline
  for (const Element& el : h.elems) {
    if ((el.name == "vertex" || el.name == "face" || el.name == "tristrips") && el.count > kMaxElements)
      fail(path, el.line, fmt::format("'{}' count {} too large (at most {})", el.name, el.count, kMaxElements));
    check_declared(path, el.line, el.count, min_entry_bytes(el, h.binary), left, "element '" + el.name + "'");
  }
}

// What the elements' entries become.
class PlySink {
 public:
  PlySink(const std::string& path, const PlyHeader& h, const PlyLayout& l) : path_(path) {
    nv_ = h.elems[l.vertex].count;
    xyz_.reserve(3 * static_cast<std::size_t>(nv_));
  }
  void vertex(int line, long long i, const double* p) {
    check_coordinates(path_, line, i, p);
    xyz_.insert(xyz_.end(), p, p + 3);
  }
  void face(int line, long long i, const std::vector<long long>& poly) {
    if (poly.size() < 3) fail(path_, line, fmt::format("face {}: {} corners (need at least 3)", i, poly.size()));
    for (long long v : poly)
      if (v < 0 || v >= nv_) fail(path_, line, fmt::format("face {}: index {} out of range [0, {})", i, v, nv_));
    fan(poly, tri_);
    check_size(line);
  }
  // A strip s0 s1 s2 s3 ... is the triangles (s0 s1 s2), (s2 s1 s3), (s2 s3 s4), ...: every other one reversed
  // to keep the orientation; -1 restarts the strip. Triangles with a repeated corner only stitch strips
  // together and are dropped.
  void strip(int line, long long i, const std::vector<long long>& s) {
    for (long long v : s)
      if (v < -1 || v >= nv_)
        fail(path_, line, fmt::format("tristrips {}: index {} out of range [0, {}) (-1 restarts a strip)", i, v, nv_));
    std::size_t start = 0;
    for (std::size_t k = 0; k < s.size(); ++k) {
      if (s[k] < 0) {
        start = k + 1;
        continue;
      }
      if (k < start + 2) continue;
      const long long a = s[k - 2], b = s[k - 1], c = s[k];
      if (a == b || b == c || a == c) continue;
      const bool odd = (k - start) % 2 == 1;
      tri_.insert(tri_.end(), {static_cast<int>(odd ? b : a), static_cast<int>(odd ? a : b), static_cast<int>(c)});
    }
    check_size(line);
  }
  Mesh mesh() const { return assemble(xyz_, tri_, path_); }

 private:
  void check_size(int line) const {
    if (tri_.size() / 3 > static_cast<std::size_t>(kMaxElements)) fail(path_, line, "too many triangles");
  }
  const std::string& path_;
  long long nv_;
  std::vector<double> xyz_;
  std::vector<int> tri_;
};

// ASCII body: one entry per line.
class PlyText {
 public:
  PlyText(const std::string& path, const std::string& data, const PlyHeader& h)
      : path_(path), lines_(data, false, h.body, h.lines + 1) {}
  void begin(const Element& el, long long i) {
    std::string_view line;
    if (!lines_.next_content(line))
      fail(path_, lines_.line(), fmt::format("file ends after {} of {} '{}' elements", i, el.count, el.name));
    split(line, t_);
    k_ = 0;
    el_ = &el;
    i_ = i;
  }
  double value(PType ty) {
    if (k_ >= t_.size()) fail(path_, line(), fmt::format("{} {}: too few values", el_->name, i_));
    double v = 0;
    long long n = 0;
    const bool ok = is_integer(ty) ? parse_int(t_[k_], n) && n >= type_range(ty).first && n <= type_range(ty).second
                                   : parse_double(t_[k_], v);
    if (!ok) fail(path_, line(), fmt::format("{} {}: bad value {}", el_->name, i_, quote(t_[k_])));
    ++k_;
    return is_integer(ty) ? static_cast<double>(n) : v;
  }
  //! A list's length, checked against the values left on the line.
  std::size_t list_length(PType count_type, PType) {
    const double n = value(count_type);
    if (n < 0) fail(path_, line(), fmt::format("{} {}: negative list length", el_->name, i_));
    if (n > static_cast<double>(t_.size() - k_))
      fail(path_, line(), fmt::format("{} {}: too few values", el_->name, i_));
    return static_cast<std::size_t>(n);
  }
  void skip(std::size_t n, PType ty) {
    for (std::size_t j = 0; j < n; ++j) value(ty);
  }
  void end() {
    if (k_ != t_.size()) fail(path_, line(), fmt::format("{} {}: {} values too many", el_->name, i_, t_.size() - k_));
  }
  void finish() {
    std::string_view line;
    if (lines_.next_content(line)) fail(path_, lines_.line(), "unexpected content after the last element");
  }
  int line() const { return lines_.line(); }

 private:
  const std::string& path_;
  Lines lines_;
  std::vector<std::string_view> t_;
  std::size_t k_ = 0;
  const Element* el_ = nullptr;
  long long i_ = 0;
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

// Binary little-endian body. Errors name the element; their "line" is where the header ended.
class PlyBinary {
 public:
  PlyBinary(const std::string& path, const std::string& data, const PlyHeader& h)
      : path_(path), p_(data.data() + h.body), end_(data.data() + data.size()), line_(h.lines) {}
  void begin(const Element& el, long long i) {
    el_ = &el;
    i_ = i;
  }
  double value(PType ty) {
    need(type_size(ty));
    const double v = binary_value(p_, ty);
    p_ += type_size(ty);
    return v;
  }
  //! A list's length, checked against the bytes left.
  std::size_t list_length(PType count_type, PType type) {
    const double n = value(count_type);
    if (n < 0) fail(path_, line_, fmt::format("'{}' element {}: negative list length", el_->name, i_));
    need(static_cast<std::size_t>(n) * type_size(type));
    return static_cast<std::size_t>(n);
  }
  void skip(std::size_t n, PType ty) {
    need(n * type_size(ty));
    p_ += n * type_size(ty);
  }
  void end() {}
  void finish() {
    if (p_ != end_) fail(path_, line_, fmt::format("{} bytes of trailing data after the last element", end_ - p_));
  }
  int line() const { return line_; }
  //! Skips `count` entries of an element of scalars only, in one step.
  bool skip_fixed(const Element& el) {
    std::size_t bytes = 0;
    for (const Prop& pr : el.props) {
      if (pr.is_list) return false;
      bytes += type_size(pr.type);
    }
    begin(el, 0);
    need(bytes * static_cast<std::size_t>(el.count));  // bounded by check_ply_counts
    p_ += bytes * static_cast<std::size_t>(el.count);
    return true;
  }

 private:
  void need(std::size_t bytes) const {
    if (static_cast<std::size_t>(end_ - p_) < bytes)
      fail(path_, line_, fmt::format("binary data ends inside '{}' element {} of {}", el_->name, i_, el_->count));
  }
  const std::string& path_;
  const char* p_;
  const char* end_;
  int line_;
  const Element* el_ = nullptr;
  long long i_ = 0;
};

template <class Body>
void read_ply_entry(Body& body, const Element& el, int e, long long i, const PlyLayout& l, PlySink& sink,
                    std::vector<long long>& list) {
  body.begin(el, i);
  double p3[3] = {0, 0, 0};
  for (std::size_t pi = 0; pi < el.props.size(); ++pi) {
    const Prop& p = el.props[pi];
    const int k = static_cast<int>(pi);
    if (!p.is_list) {
      const double v = body.value(p.type);
      if (e == l.vertex)
        for (int c = 0; c < 3; ++c)
          if (l.xyz[c] == k) p3[c] = v;
      continue;
    }
    const std::size_t n = body.list_length(p.count_type, p.type);
    const bool faces = e == l.face && k == l.face_list, strips = e == l.strips && k == l.strip_list;
    if (!faces && !strips) {
      body.skip(n, p.type);
      continue;
    }
    list.clear();
    list.reserve(n);  // list_length checked that n values follow
    for (std::size_t j = 0; j < n; ++j) list.push_back(static_cast<long long>(body.value(p.type)));
    if (faces) sink.face(body.line(), i, list);
    else sink.strip(body.line(), i, list);
  }
  body.end();
  if (e == l.vertex) sink.vertex(body.line(), i, p3);
}

template <class Body>
void read_ply_body(Body& body, const PlyHeader& h, const PlyLayout& l, PlySink& sink) {
  std::vector<long long> list;
  for (std::size_t e = 0; e < h.elems.size(); ++e) {
    const Element& el = h.elems[e];
    if constexpr (std::is_same_v<Body, PlyBinary>) {
      if (static_cast<int>(e) != l.vertex && body.skip_fixed(el)) continue;
    }
    for (long long i = 0; i < el.count; ++i) read_ply_entry(body, el, static_cast<int>(e), i, l, sink, list);
  }
  body.finish();
}

Mesh read_ply(const std::string& path, const std::string& data) {
  const PlyHeader h = parse_ply_header(path, data);
  const PlyLayout l = locate(path, h);
  check_ply_counts(path, h, data.size() - h.body);
  PlySink sink(path, h, l);
  if (!h.binary) {
    PlyText body(path, data, h);
    read_ply_body(body, h, l, sink);
  } else {
    const std::uint16_t probe = 1;
    unsigned char b;
    std::memcpy(&b, &probe, 1);
    if (b != 1) throw InputError(path + ": binary PLY needs a little-endian host");
    PlyBinary body(path, data, h);
    read_ply_body(body, h, l, sink);
  }
  return sink.mesh();
}

// ---------------------------------------------------------------- OBJ
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
