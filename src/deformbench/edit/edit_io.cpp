#include "edit/edit_io.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "core/input_file.h"
#include "edit/selection.h"
#include "edit/transform.h"
#include "mesh/mesh_io.h"

namespace db {

namespace {

namespace fs = std::filesystem;

// What a line of an edit-side text file (.edit, .sel, .def, targets) sensibly holds: a key and a path, a few
// numbers, a comment.
constexpr std::size_t kMaxLine = 64 << 10;
// What a .edit or .def file sensibly holds: eight keys, one 4x4 matrix, with comments.
constexpr std::uint64_t kSmallFile = 1 << 20;
// Per vertex of the mesh, what a .sel line or an index-list entry sensibly takes (comments and padding included).
constexpr std::uint64_t kBytesPerVertex = 64;

// Calls fn(line number, line) for every line of a text file, streaming: a selection of millions of vertices is
// never held as millions of strings. The file is refused before reading when larger than max_bytes, and at a
// line longer than max_line.
void each_line(const std::string& path, const char* what, const std::function<void(int, const std::string&)>& fn,
               std::uint64_t max_bytes = kSmallFile, std::size_t max_line = kMaxLine) {
  InputFile(path, what, max_bytes).each_line(max_line, fn);
}

// The bound of a file with a line or an entry per vertex of a mesh with num_vertices (unknown: < 0).
std::uint64_t per_vertex_bound(int num_vertices) {
  return num_vertices < 0 ? kAnySize : kSmallFile + kBytesPerVertex * static_cast<std::uint64_t>(num_vertices);
}

// Drops a '#' comment and surrounding whitespace.
std::string strip(const std::string& line) {
  std::string s = line.substr(0, line.find('#'));
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

std::vector<std::string> tokens(const std::string& s, const char* seps) {
  std::vector<std::string> out;
  std::size_t b = s.find_first_not_of(seps);
  while (b != std::string::npos) {
    const std::size_t e = s.find_first_of(seps, b);
    out.push_back(s.substr(b, e == std::string::npos ? std::string::npos : e - b));
    b = e == std::string::npos ? e : s.find_first_not_of(seps, e);
  }
  return out;
}

bool to_double(std::string t, double& v) {
  if (!t.empty() && t[0] == '+') t.erase(0, 1);
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  return !t.empty() && r.ec == std::errc() && r.ptr == t.data() + t.size();
}

bool to_int(std::string t, long long& v) {
  if (!t.empty() && t[0] == '+') t.erase(0, 1);
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  return !t.empty() && r.ec == std::errc() && r.ptr == t.data() + t.size();
}

bool exists(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

// Re-throws an InputError with a prefix, unless the message already starts with it.
template <class F>
auto prefixed(const std::string& prefix, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const InputError& e) {
    const std::string msg = e.what();
    if (msg.rfind(prefix, 0) == 0) throw;
    throw InputError(prefix + ": " + msg);
  }
}

// The stem's mesh as load_stem reads it: the first of STEM.off, .ply, .obj, .stl that exists ("" if none).
std::string stem_mesh(const std::string& stem) {
  for (const std::string& ext : mesh_extensions())
    if (exists(stem + ext)) return stem + ext;
  return {};
}

// "data/bs08/bar.off" and "data/bs08/bar" name the same stem.
std::string stem_of(const std::string& spec) {
  const std::string ext = fs::path(spec).extension().string();
  const auto& meshes = mesh_extensions();
  if (std::find(meshes.begin(), meshes.end(), ext) != meshes.end() || ext == ".sel" || ext == ".def")
    return spec.substr(0, spec.size() - ext.size());
  return spec;
}

bool is_edit_file(const std::string& spec) { return fs::path(spec).extension() == ".edit"; }

// A path written in a .edit file is relative to that file.
std::string resolve(const fs::path& dir, const std::string& p) {
  return fs::path(p).is_relative() ? (dir / p).string() : p;
}

struct Entry {
  std::string value;
  int line;
};

// The `key = value` lines of a .edit file: known keys, each once, none empty. \throw InputError naming the file
// and line.
std::map<std::string, Entry> read_edit_entries(const std::string& path) {
  std::map<std::string, Entry> kv;
  static const char* known[] = {"mesh", "name", "sel", "def", "roi", "handle", "transform", "targets"};
  each_line(path, "edit", [&](int ln, const std::string& line) {
    // A UTF-8 byte-order mark (some editors write one) is no part of the first key.
    const bool bom = ln == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0;
    const std::string s = strip(bom ? line.substr(3) : line);
    if (s.empty()) return;
    const auto eq = s.find('=');
    if (eq == std::string::npos) throw InputError(fmt::format("{}: line {}: expected 'key = value'", path, ln));
    const std::string key = strip(s.substr(0, eq)), value = strip(s.substr(eq + 1));
    if (std::find(std::begin(known), std::end(known), key) == std::end(known))
      throw InputError(fmt::format("{}: line {}: unknown key '{}' (known: mesh, name, sel, def, roi, handle, transform, "
                                   "targets)",
                                   path, ln, key));
    if (value.empty()) throw InputError(fmt::format("{}: line {}: empty value for '{}'", path, ln, key));
    if (kv.count(key))
      throw InputError(fmt::format("{}: line {}: '{}' given twice (first on line {})", path, ln, key, kv[key].line));
    kv[key] = {value, ln};
  });
  return kv;
}

// A selection that selects nothing: name the spec and where the mesh lies, the usual cause being coordinates of
// another model or units.
void check_not_empty(const std::vector<int>& ids, const char* what, const std::string& spec, const Mesh& mesh,
                     const std::string& where) {
  if (!ids.empty()) return;
  const Eigen::RowVector3d lo = mesh.V.colwise().minCoeff(), hi = mesh.V.colwise().maxCoeff();
  throw InputError(fmt::format("{}: {} selection '{}' selects no vertex (the mesh spans ({:g}, {:g}, {:g}) to ({:g}, "
                               "{:g}, {:g}))",
                               where, what, spec, lo(0), lo(1), lo(2), hi(0), hi(1), hi(2)));
}

}  // namespace

std::vector<Role> read_sel(const std::string& path, int num_vertices) {
  std::vector<Role> roles;
  if (num_vertices >= 0) roles.reserve(num_vertices);
  each_line(path, "selection", [&](int ln, const std::string& line) {
    const std::string s = strip(line);
    if (s.empty()) return;
    if (num_vertices >= 0 && static_cast<long>(roles.size()) == num_vertices)
      throw InputError(fmt::format("{}: line {}: selection has more than {} entries but the mesh has {} vertices", path,
                                   ln, num_vertices, num_vertices));
    if (s == "0") roles.push_back(Role::Fixed);
    else if (s == "1") roles.push_back(Role::Free);
    else if (s == "2") roles.push_back(Role::Handle);
    else throw InputError(fmt::format("{}: line {}: invalid status '{}' (expected 0, 1 or 2)", path, ln, s));
  }, per_vertex_bound(num_vertices));
  if (num_vertices >= 0 && static_cast<long>(roles.size()) != num_vertices)
    throw InputError(fmt::format("{}: selection has {} entries but the mesh has {} vertices", path, roles.size(),
                                 num_vertices));
  return roles;
}

Mat4 read_def(const std::string& path) {
  Mat4 T;
  int row = 0;
  each_line(path, "transform", [&](int ln, const std::string& line) {
    const std::string s = strip(line);
    if (s.empty()) return;
    if (row == 4) throw InputError(fmt::format("{}: line {}: unexpected content after the 4x4 matrix", path, ln));
    const auto t = tokens(s, " \t,");
    if (t.size() != 4)
      throw InputError(fmt::format("{}: line {}: expected 4 numbers per matrix row, got {}", path, ln, t.size()));
    for (int c = 0; c < 4; ++c)
      if (!to_double(t[c], T(row, c)) || !std::isfinite(T(row, c)))
        throw InputError(fmt::format("{}: line {}: bad number '{}'", path, ln, t[c]));
    ++row;
  });
  if (row != 4) throw InputError(fmt::format("{}: expected 4 matrix rows, got {}", path, row));
  if (T.row(3) != Eigen::RowVector4d(0, 0, 0, 1))
    throw InputError(fmt::format("{}: not an affine transform (last row {} {} {} {}, expected 0 0 0 1)", path, T(3, 0),
                                 T(3, 1), T(3, 2), T(3, 3)));
  return T;
}

Points read_targets(const std::string& path, long long max_rows) {
  std::vector<double> xyz;
  each_line(path, "targets", [&](int ln, const std::string& line) {
    const std::string s = strip(line);
    if (s.empty()) return;
    if (max_rows >= 0 && static_cast<long long>(xyz.size() / 3) == max_rows)
      throw InputError(fmt::format("{}: line {}: more than {} target positions ({} frames of the handle, the most "
                                   "a run interpolates)",
                                   path, ln, max_rows, kMaxFrames));
    const auto t = tokens(s, " \t,");
    if (t.size() != 3) throw InputError(fmt::format("{}: line {}: expected 3 numbers (x y z), got {}", path, ln, t.size()));
    for (const std::string& tok : t) {
      double v;
      if (!to_double(tok, v) || !std::isfinite(v))
        throw InputError(fmt::format("{}: line {}: bad number '{}' (a finite coordinate expected)", path, ln, tok));
      xyz.push_back(v);
    }
  }, kAnySize);
  if (xyz.empty()) throw InputError(path + ": no target positions");
  Points P(static_cast<Eigen::Index>(xyz.size() / 3), 3);
  for (Eigen::Index r = 0; r < P.rows(); ++r)
    for (int c = 0; c < 3; ++c) P(r, c) = xyz[static_cast<std::size_t>(3 * r + c)];
  return P;
}

Edit read_bs08_edit(const std::string& sel_path, const std::string& def_path, int num_vertices) {
  Edit e;
  e.name = fs::path(sel_path).stem().string();
  e.roles = read_sel(sel_path, num_vertices);
  e.transform = read_def(def_path);
  return e;
}

std::vector<int> read_index_list(const std::string& path, int num_vertices) {
  std::vector<int> out;
  const std::uint64_t bound = per_vertex_bound(num_vertices);
  each_line(path, "index list", [&](int ln, const std::string& line) {
    for (const std::string& t : tokens(strip(line), " \t\r,")) {
      long long v;
      if (!to_int(t, v)) throw InputError(fmt::format("{}: line {}: '{}' is not a vertex index", path, ln, t));
      if (v < 0 || v > INT32_MAX) throw InputError(fmt::format("{}: line {}: vertex index {} out of range", path, ln, v));
      out.push_back(static_cast<int>(v));
    }
  }, bound, bound);  // all ids on one line is fine
  return out;
}

Edit edit_from_lists(int num_vertices, const std::vector<int>& roi, const std::vector<int>& handle, const Mat4& T) {
  auto check = [&](const std::vector<int>& ids, const char* what) {
    for (int v : ids)
      if (v < 0 || v >= num_vertices)
        throw InputError(fmt::format("{} vertex {} out of range [0, {})", what, v, num_vertices));
  };
  check(roi, "region-of-interest");
  check(handle, "handle");
  if (roi.empty()) throw InputError("the region of interest is empty");
  if (handle.empty()) throw InputError("the handle is empty");
  Edit e;
  e.transform = T;
  e.roles.assign(num_vertices, Role::Fixed);
  for (int v : roi) e.roles[v] = Role::Free;
  std::vector<int> outside;
  for (int v : handle)
    if (e.roles[v] == Role::Fixed) outside.push_back(v);
  if (!outside.empty())
    throw InputError(fmt::format("handle vertex {} is outside the region of interest ({} of the {} handle vertices "
                                 "are); the handle must be part of it",
                                 outside.front(), outside.size(), handle.size()));
  for (int v : handle) e.roles[v] = Role::Handle;
  return e;
}

namespace {

EditCase finish(EditCase c, const std::string& where) {
  prefixed(where, [&] { validate_edit(c.mesh, c.edit); });
  return c;
}

EditCase load_stem(const std::string& stem) {
  EditCase c;
  c.mesh_path = stem_mesh(stem);
  const std::string sel = stem + ".sel", def = stem + ".def";
  if (c.mesh_path.empty() || !exists(sel) || !exists(def)) {
    const std::string lacking = c.mesh_path.empty() ? stem + ".off" : !exists(sel) ? sel : def;
    std::error_code ec;
    throw InputError(fmt::format("edit case '{}': not a .edit file, and not a stem with .off (or .ply/.obj/.stl), .sel "
                                 "and .def files ({} {})",
                                 stem, lacking, fs::exists(lacking, ec) ? "is not a regular file" : "is missing"));
  }
  c.mesh = read_mesh(c.mesh_path);
  // Non-manifold meshes load: uniform lap and tf deform them; cotan and lri refuse them (make_deformer).
  prefixed(c.mesh_path, [&] { validate_mesh(c.mesh, Manifold::Allowed); });
  c.edit = read_bs08_edit(sel, def, c.mesh.num_vertices());
  c.edit.name = fs::path(stem).filename().string();
  return finish(std::move(c), stem);
}

EditCase load_edit_file(const std::string& path) {
  auto kv = read_edit_entries(path);
  auto has = [&](const char* k) { return kv.count(k) > 0; };
  auto at = [&](const char* k) { return fmt::format("{}: line {}", path, kv.at(k).line); };
  if (!has("mesh")) throw InputError(path + ": missing 'mesh = PATH'");
  if (has("sel") && (has("roi") || has("handle")))
    throw InputError(path + ": give either 'sel' or 'roi' + 'handle', not both");
  if (!has("sel") && !(has("roi") && has("handle")))
    throw InputError(path + ": missing the selection ('sel = FILE', or both 'roi' and 'handle')");
  if (has("def") + has("transform") + has("targets") != 1)
    throw InputError(path + ": give exactly one of 'def = FILE', 'transform = SPEC' and 'targets = FILE'");

  const fs::path dir = fs::path(path).parent_path();

  EditCase c;
  c.mesh_path = resolve(dir, kv["mesh"].value);
  c.mesh = prefixed(at("mesh"), [&] { return read_mesh(c.mesh_path); });
  // Mesh first: k-ring selections need a valid adjacency.
  prefixed(c.mesh_path, [&] { validate_mesh(c.mesh, Manifold::Allowed); });
  const int nv = c.mesh.num_vertices();

  const Mat4 T = has("def")         ? prefixed(at("def"), [&] { return read_def(resolve(dir, kv["def"].value)); })
                 : has("transform") ? prefixed(at("transform"),
                                               [&] { return parse_transform(kv["transform"].value, dir.string()); })
                                    : Mat4::Identity();
  if (has("sel")) {
    c.edit.roles = prefixed(at("sel"), [&] { return read_sel(resolve(dir, kv["sel"].value), nv); });
    c.edit.transform = T;
  } else {
    const auto roi = prefixed(at("roi"), [&] { return select_by_spec(c.mesh, kv["roi"].value, dir.string()); });
    check_not_empty(roi, "roi", kv["roi"].value, c.mesh, at("roi"));
    const auto handle =
        prefixed(at("handle"), [&] { return select_by_spec(c.mesh, kv["handle"].value, dir.string()); });
    check_not_empty(handle, "handle", kv["handle"].value, c.mesh, at("handle"));
    c.edit = prefixed(path, [&] { return edit_from_lists(nv, roi, handle, T); });
  }
  if (has("targets"))
    c.edit.targets = prefixed(at("targets"), [&] {
      return read_targets(resolve(dir, kv["targets"].value), kMaxFrames * c.edit.count(Role::Handle));
    });
  c.edit.name = has("name") ? kv["name"].value : fs::path(path).stem().string();
  return finish(std::move(c), path);
}

}  // namespace

EditCase load_edit_case(const std::string& spec) {
  return is_edit_file(spec) ? load_edit_file(spec) : load_stem(stem_of(spec));
}

std::vector<std::string> edit_case_files(const std::string& spec) {
  if (!is_edit_file(spec)) {
    const std::string stem = stem_of(spec), mesh = stem_mesh(stem);
    return {mesh.empty() ? stem + ".off" : mesh, stem + ".sel", stem + ".def"};
  }
  const auto kv = read_edit_entries(spec);
  const fs::path dir = fs::path(spec).parent_path();
  std::vector<std::string> files{spec};
  auto file_after = [&](const char* key, const std::string& prefix) {
    const auto it = kv.find(key);
    if (it != kv.end() && it->second.value.rfind(prefix, 0) == 0)
      files.push_back(resolve(dir, strip(it->second.value.substr(prefix.size()))));
  };
  for (const char* key : {"mesh", "sel", "def", "targets"}) file_after(key, "");
  file_after("roi", "indices:");
  file_after("handle", "indices:");
  file_after("transform", "def:");
  return files;
}

}  // namespace db
