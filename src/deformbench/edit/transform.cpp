#include "edit/transform.h"

#include <charconv>
#include <cmath>
#include <filesystem>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include "solvers/base/error.h"
#include "edit/edit_io.h"

namespace db {

namespace {

std::vector<std::string> split_on(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::size_t b = 0;
  while (true) {
    const std::size_t e = s.find(sep, b);
    out.push_back(s.substr(b, e == std::string::npos ? std::string::npos : e - b));
    if (e == std::string::npos) break;
    b = e + 1;
  }
  return out;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

}  // namespace

std::vector<double> parse_numbers(const std::string& text, std::size_t count, const std::string& what) {
  const std::vector<std::string> parts = split_on(text, ',');
  if (parts.size() != count)
    throw InputError(fmt::format("{}: expected {} comma-separated numbers, got {} in '{}'", what, count, parts.size(), text));
  std::vector<double> out;
  for (const std::string& raw : parts) {
    std::string t = trim(raw);
    if (!t.empty() && t[0] == '+') t.erase(0, 1);
    double v = 0;
    const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    if (t.empty() || r.ec != std::errc() || r.ptr != t.data() + t.size() || !std::isfinite(v))
      throw InputError(fmt::format("{}: bad number '{}' in '{}'", what, trim(raw), text));
    out.push_back(v);
  }
  return out;
}

Mat4 translation(const Vec3& t) {
  Mat4 T = Mat4::Identity();
  T.topRightCorner<3, 1>() = t;
  return T;
}

Mat4 rotation_about_axis(const Vec3& axis, double degrees, const Vec3& point) {
  const double n = axis.norm();
  if (!(n > 0) || !std::isfinite(n) || !std::isfinite(degrees) || !point.allFinite())
    throw InputError(fmt::format("rotation: axis ({}, {}, {}) must be non-zero and finite", axis(0), axis(1), axis(2)));
  constexpr double kPi = 3.14159265358979323846;
  const Mat3 R = Eigen::AngleAxisd(degrees * kPi / 180.0, axis / n).toRotationMatrix();
  Mat4 T = Mat4::Identity();
  T.topLeftCorner<3, 3>() = R;
  T.topRightCorner<3, 1>() = point - R * point;  // x -> R (x - p) + p
  return T;
}

Mat4 parse_transform(const std::string& spec) { return parse_transform(spec, ""); }

Mat4 parse_transform(const std::string& spec_in, const std::string& base_dir) {
  const std::string spec = trim(spec_in);
  const std::string what = "transform '" + spec + "'";
  const std::size_t colon = spec.find(':');
  const std::string kind = spec.substr(0, colon);
  const std::string rest = colon == std::string::npos ? "" : spec.substr(colon + 1);
  auto vec3 = [&](const std::string& s) {
    const auto v = parse_numbers(s, 3, what);
    return Vec3(v[0], v[1], v[2]);
  };
  if (colon == std::string::npos) {
    // fall through to the error below
  } else if (kind == "translate") {
    return translation(vec3(rest));
  } else if (kind == "rotate") {
    const std::vector<std::string> parts = split_on(rest, ':');
    if (parts.size() != 2 && parts.size() != 3)
      throw InputError(what + ": expected rotate:DEG:ax,ay,az[:px,py,pz]");
    const double deg = parse_numbers(parts[0], 1, what)[0];
    const Vec3 point = parts.size() == 3 ? vec3(parts[2]) : Vec3::Zero();
    try {
      return rotation_about_axis(vec3(parts[1]), deg, point);
    } catch (const InputError& e) {
      throw InputError(what + ": " + e.what());
    }
  } else if (kind == "matrix") {
    const auto v = parse_numbers(rest, 16, what);
    Mat4 T;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) T(r, c) = v[4 * r + c];
    if (T.row(3) != Eigen::RowVector4d(0, 0, 0, 1))
      throw InputError(what + ": not affine (last row must be 0,0,0,1)");
    return T;
  } else if (kind == "def") {
    if (rest.empty()) throw InputError(what + ": expected def:PATH");
    namespace fs = std::filesystem;
    fs::path p(rest);
    if (p.is_relative() && !base_dir.empty()) p = fs::path(base_dir) / p;
    return read_def(p.string());
  }
  throw InputError(what + ": expected translate:x,y,z | rotate:DEG:ax,ay,az[:px,py,pz] | matrix:m00,...,m33 | def:PATH");
}

}  // namespace db
