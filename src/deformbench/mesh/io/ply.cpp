#include "mesh/io/ply.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "mesh/io/common.h"

namespace db::io {

namespace {

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
      for (const Element& e : h.elems)
        if (e.name == t[1]) fail(path, ln, fmt::format("element '{}' declared twice (first on line {})", e.name, e.line));
      h.elems.push_back({std::string(t[1]), n, {}, ln});
    } else if (t[0] == "property") {
      if (h.elems.empty()) fail(path, ln, "property before any element");
      Element& el = h.elems.back();
      el.props.push_back(parse_ply_property(path, ln, t));
      for (std::size_t k = 0; k + 1 < el.props.size(); ++k)
        if (el.props[k].name == el.props.back().name)
          fail(path, ln, fmt::format("'{}' element: property '{}' declared twice", el.name, el.props[k].name));
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

}  // namespace

Mesh read_ply(const std::string& path, const std::string& data) {
  const PlyHeader h = parse_ply_header(path, data);
  const PlyLayout l = locate(path, h);
  check_ply_counts(path, h, data.size() - h.body);
  PlySink sink(path, h, l);
  if (!h.binary) {
    PlyText body(path, data, h);
    read_ply_body(body, h, l, sink);
  } else {
    require_little_endian_host(path, "binary PLY");
    PlyBinary body(path, data, h);
    read_ply_body(body, h, l, sink);
  }
  return sink.mesh();
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

}  // namespace db::io
