// Mesh file formats: exact round trips, the accepted variants of each format, and strict rejection of bad files.
#include <gtest/gtest.h>

#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "solvers/base/error.h"
#include "mesh/mesh.h"
#include "mesh/mesh_io.h"
#include "mesh/procedural.h"
#include "test_util.h"

namespace {

using namespace db;
namespace fs = std::filesystem;

class MeshIo : public TempDirTest {};

// Coordinates that a lossy writer would change: thirds, tiny and huge magnitudes, negative zero.
Mesh awkward_mesh() {
  Mesh m = make_cylinder(4, 5, 1.0 / 3.0, 7.1);
  m.V(0, 0) = 1e-300;
  m.V(1, 1) = -0.0;
  m.V(2, 2) = 1.2345678901234567e20;
  m.V(3, 0) = -std::nextafter(0.1, 1.0);
  return m;
}

std::string slurp(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void expect_same(const Mesh& a, const Mesh& b) {
  ASSERT_EQ(a.V.rows(), b.V.rows());
  ASSERT_EQ(a.F.rows(), b.F.rows());
  for (Eigen::Index i = 0; i < a.V.size(); ++i) {
    // Bitwise: also distinguishes -0 from 0.
    EXPECT_EQ(std::memcmp(a.V.data() + i, b.V.data() + i, sizeof(double)), 0) << "coordinate " << i;
  }
  EXPECT_TRUE((a.F.array() == b.F.array()).all());
}

TEST_F(MeshIo, RoundTripIsExactInEveryFormat) {
  const Mesh m = awkward_mesh();
  for (const char* ext : {".off", ".ply", ".obj"}) {
    SCOPED_TRACE(ext);
    const std::string p = path(std::string("rt") + ext);
    write_mesh(p, m);
    const Mesh r = read_mesh(p);
    expect_same(m, r);
    EXPECT_EQ(r.name, "rt");
  }
}

TEST_F(MeshIo, WriterIsDeterministicAndLeavesNoTemporary) {
  const Mesh m = awkward_mesh();
  for (const char* ext : {".off", ".ply", ".obj", ".stl"}) {
    write_mesh(path(std::string("a") + ext), m);
    write_mesh(path(std::string("b") + ext), m);
    EXPECT_EQ(slurp(path(std::string("a") + ext)), slurp(path(std::string("b") + ext))) << ext;
  }
  for (const auto& e : fs::directory_iterator(dir_))
    EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << e.path();
}

TEST_F(MeshIo, PlyWriterDeclaresDoubleVertices) {
  write_mesh(path("h.ply"), make_cylinder(2, 3, 1, 1));
  const std::string s = slurp(path("h.ply"));
  EXPECT_NE(s.find("format binary_little_endian 1.0\n"), std::string::npos);
  EXPECT_NE(s.find("property double x\n"), std::string::npos);
  EXPECT_NE(s.find("property list uchar int vertex_indices\n"), std::string::npos);
}

TEST_F(MeshIo, OffVariants) {
  // Comments, header and counts on one line, a quad (fan-triangulated), blank lines.
  Mesh m = read_mesh(write("a.off", "OFF 4 1 0 # header\n# comment\n\n0 0 0\n1 0 0\n1 1 0 # c\n0 1 0\n4 0 1 2 3\n"));
  ASSERT_EQ(m.num_vertices(), 4);
  ASSERT_EQ(m.num_faces(), 2);
  EXPECT_EQ(m.F.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(m.F.row(1), Eigen::RowVector3i(0, 2, 3));
  // COFF: RGBA per vertex, a face colour; CRLF line ends.
  m = read_mesh(write("c.off", "COFF\r\n3 1 0\r\n0 0 0 192 192 192 255\r\n1 0 0 1 2 3 4\r\n0 1 0 5 6 7 8\r\n3 0 1 2 255 0 0\r\n"));
  EXPECT_EQ(m.num_faces(), 1);
  EXPECT_EQ(m.V(1, 0), 1.0);
  // NOFF: normals skipped.
  m = read_mesh(write("n.off", "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n"));
  EXPECT_EQ(m.V(2, 1), 1.0);
  // No header keyword at all.
  m = read_mesh(write("h.off", "3 1\n0 0 0\n1 0 0\n0 1 0\n3 2 1 0\n"));
  EXPECT_EQ(m.F.row(0), Eigen::RowVector3i(2, 1, 0));
}

TEST_F(MeshIo, OffMalformed) {
  const std::string v3 = "0 0 0\n1 0 0\n0 1 0\n";
  // Counts the bytes left cannot hold are refused before reading on; a short line only when reached.
  expect_input_error([&] { read_mesh(write("t.off", "OFF\n3 2 0\n" + v3 + "3 0 1 2\n")); },
                     "line 2: the header's face count declares 2 entries");
  expect_input_error([&] { read_mesh(write("v.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n")); },
                     "line 2: the header's vertex count declares 3 entries");
  expect_input_error([&] { read_mesh(write("s.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n# padding padding padding\n")); },
                     "file ends after 2 of 3 vertices");
  expect_input_error([&] { read_mesh(write("c.off", "OFF\n3 x 0\n" + v3 + "3 0 1 2\n")); }, "line 2: bad face count");
  expect_input_error([&] { read_mesh(write("g.off", "OFF\n3 1 0\n0 0 0\n1 zz 0\n0 1 0\n3 0 1 2\n")); },
                     "line 4: vertex 1: bad number 'zz'");
  // Short lines padded with blanks, so the bytes could hold the declared counts and the line itself is at fault.
  expect_input_error([&] { read_mesh(write("w.off", "OFF\n3 1 0\n0 0  \n1 0 0\n0 1 0\n3 0 1 2\n")); },
                     "vertex 0: expected 3 values, got 2");
  expect_input_error([&] { read_mesh(write("r.off", "OFF\n3 1 0\n" + v3 + "3 0 1 3\n")); }, "index 3 out of range");
  expect_input_error([&] { read_mesh(write("n.off", "OFF\n3 1 0\n" + v3 + "3 0 -1 2\n")); }, "index -1 out of range");
  expect_input_error([&] { read_mesh(write("f.off", "OFF\n3 1 0\n" + v3 + "3 0 1  \n")); }, "expected 3 indices");
  expect_input_error([&] { read_mesh(write("d.off", "OFF\n3 1 0\n" + v3 + "2 0 1  \n")); }, "need at least 3");
  expect_input_error([&] { read_mesh(write("e.off", "OFF\n3 1 0\n" + v3 + "3 0 1 2\n3 0 1 2\n")); },
                     "unexpected content after 3 vertices and 1 faces");
  expect_input_error([&] { read_mesh(write("h.off", "nOFF\n3 1 0\n" + v3 + "3 0 1 2\n")); }, "unsupported OFF variant");
  expect_input_error([&] { read_mesh(write("z.off", "")); }, "empty file");
  expect_input_error([&] { read_mesh(write("x.off", "PLY\n")); }, "expected an OFF header");
}

TEST_F(MeshIo, PlyAsciiWithExtraPropertiesAndElements) {
  const std::string ply =
      "ply\nformat ascii 1.0\ncomment made by hand\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float nx\nproperty double z\nproperty uchar red\nelement face 1\nproperty uchar flags\n"
      "property list uchar int vertex_index\nelement edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n"
      "0 0 9 0 255\n1 0 9 0.5 255\n1 1 9 0 255\n0 1 9 0 255\n7 4 0 1 2 3\n0 1\n";
  const Mesh m = read_mesh(write("a.ply", ply));
  ASSERT_EQ(m.num_vertices(), 4);
  ASSERT_EQ(m.num_faces(), 2);
  EXPECT_EQ(m.V.row(1), Eigen::RowVector3d(1, 0, 0.5));
  EXPECT_EQ(m.F.row(1), Eigen::RowVector3i(0, 2, 3));
}

std::string binary_ply_float_uint() {
  std::string s =
      "ply\r\nformat binary_little_endian 1.0\r\nelement vertex 3\r\nproperty float x\r\nproperty float y\r\n"
      "property float z\r\nproperty float quality\r\nelement face 1\r\nproperty list int uint vertex_indices\r\n"
      "end_header\r\n";
  for (int i = 0; i < 3; ++i) {
    const float v[4] = {static_cast<float>(i == 1), static_cast<float>(i == 2), 0.25f, 9.f};
    s.append(reinterpret_cast<const char*>(v), sizeof(v));
  }
  const std::int32_t n = 3;
  const std::uint32_t idx[3] = {0, 1, 2};
  s.append(reinterpret_cast<const char*>(&n), 4);
  s.append(reinterpret_cast<const char*>(idx), sizeof(idx));
  return s;
}

TEST_F(MeshIo, PlyBinaryFloatCoordinatesIntCountUintIndices) {
  const Mesh m = read_mesh(write("b.ply", binary_ply_float_uint()));
  ASSERT_EQ(m.num_vertices(), 3);
  EXPECT_EQ(m.V.row(2), Eigen::RowVector3d(0, 1, 0.25));
  EXPECT_EQ(m.F.row(0), Eigen::RowVector3i(0, 1, 2));
}

TEST_F(MeshIo, PlyMalformed) {
  const std::string good = binary_ply_float_uint();
  expect_input_error([&] { read_mesh(write("t.ply", good.substr(0, good.size() - 3))); }, "binary data ends inside 'face'");
  expect_input_error([&] { read_mesh(write("x.ply", good + "junk")); }, "trailing data");
  expect_input_error([&] { read_mesh(write("h.ply", "ply\nformat ascii 1.0\nelement vertex 0\n")); }, "no end_header");
  expect_input_error([&] { read_mesh(write("m.ply", "plyx\n")); }, "not a PLY file");
  expect_input_error(
      [&] { read_mesh(write("e.ply", "ply\nformat binary_big_endian 1.0\nend_header\n")); }, "binary_big_endian");
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
  expect_input_error([&] { read_mesh(write("r.ply", head + "3 0 1 5\n")); }, "line 13: face 0: index 5 out of range");
  expect_input_error([&] { read_mesh(write("f.ply", head + "3 0 1\n")); }, "line 13: face 0: too few values");
  expect_input_error([&] { read_mesh(write("g.ply", head + "3 0 1 2 4\n")); }, "values too many");
  expect_input_error([&] { read_mesh(write("b.ply", head + "3 0 1 x\n")); }, "bad value 'x'");
  expect_input_error([&] { read_mesh(write("c.ply", head)); }, "line 7: element 'face' declares 1 entries");
  expect_input_error([&] { read_mesh(write("d.ply", head + "\n\n\n")); }, "file ends after 0 of 1 'face' elements");
  expect_input_error(
      [&] {
        read_mesh(write("n.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty double x\nproperty double y\n"
                                 "element face 0\nproperty list uchar int vertex_indices\nend_header\n0 0\n"));
      },
      "no 'z' property");
  expect_input_error([&] { read_mesh(write("p.ply", "ply\nformat ascii 1.0\nproperty int x\nend_header\n")); },
                     "property before any element");
}

TEST_F(MeshIo, ObjVariants) {
  const std::string obj =
      "# test\nmtllib a.mtl\no thing\nv 0 0 0\nv 1 0 0\nv 1 1 0 0.5 0.5 0.5\nv 0 1 0\nvt 0 0\nvn 0 0 1\n"
      "g group\ns off\nusemtl m\nf 1/1/1 2/1/1 3/1/1\nf 1//1 3//1 4//1\nf -4 -2 -1\nf 1/1 2/1 3/1 4/1\n";
  const Mesh m = read_mesh(write("a.obj", obj));
  ASSERT_EQ(m.num_vertices(), 4);
  ASSERT_EQ(m.num_faces(), 5);
  EXPECT_EQ(m.F.row(1), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(m.F.row(2), Eigen::RowVector3i(0, 2, 3));  // negative indices count back from the last vertex
  EXPECT_EQ(m.F.row(4), Eigen::RowVector3i(0, 2, 3));
}

TEST_F(MeshIo, ObjMalformed) {
  const std::string v3 = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  expect_input_error([&] { read_mesh(write("a.obj", v3 + "f 1 2 4\n")); }, "line 4: face: index 4 out of range");
  expect_input_error([&] { read_mesh(write("b.obj", v3 + "f 0 1 2\n")); }, "index 0");
  expect_input_error([&] { read_mesh(write("c.obj", v3 + "f 1 2 -4\n")); }, "index -4 out of range");
  expect_input_error([&] { read_mesh(write("d.obj", v3 + "f 1 2 x\n")); }, "bad index 'x'");
  expect_input_error([&] { read_mesh(write("e.obj", v3 + "f 1 2 3/a\n")); }, "bad index '3/a'");
  expect_input_error([&] { read_mesh(write("f.obj", v3 + "bogus 1\n")); }, "line 4: unknown statement 'bogus'");
  expect_input_error([&] { read_mesh(write("g.obj", "v 1 2\n")); }, "line 1: vertex: expected 3 coordinates");
  expect_input_error([&] { read_mesh(write("h.obj", "v 1 2 q\n")); }, "bad number 'q'");
  expect_input_error([&] { read_mesh(write("i.obj", v3 + "f 1 2\n")); }, "need at least 3");
}

TEST_F(MeshIo, UnreadableOrUnknown) {
  expect_input_error([&] { read_mesh(path("missing.off")); }, "cannot open mesh file: " + path("missing.off"));
  expect_input_error([&] { read_mesh(dir_.string() + "/sub.off"); }, "cannot open mesh file");
  expect_input_error([&] { read_mesh(write("a.stp", "solid")); }, "unknown mesh extension '.stp'");
  expect_input_error([&] { write_mesh(path("a.stp"), make_cylinder(2, 3, 1, 1)); }, "unknown mesh extension");
  fs::create_directories(dir_ / "sub.off");
  expect_input_error([&] { read_mesh(path("sub.off")); }, "cannot open mesh file");
}

TEST_F(MeshIo, ErrorsNameTheFile) {
  const std::string p = write("named.off", "OFF\n1 0 0\nabc 0 0\n");
  expect_input_error([&] { read_mesh(p); }, p + ": line 3:");
}

TEST_F(MeshIo, RealCgalColouredOff) {
  const std::string p = DEFORMBENCH_SOURCE_DIR "/data/meshes/cactus.off";
  ASSERT_TRUE(fs::exists(p)) << p << " is missing: run scripts/data.sh (./run test does)";
  const Mesh m = read_mesh(p);
  EXPECT_NO_THROW(validate_mesh(m));
  write_mesh(path("cactus.ply"), m);
  expect_same(m, read_mesh(path("cactus.ply")));
}

// ---------------------------------------------------------------- counts checked against the bytes left (item 5)
std::string ply_head(const std::string& format, const std::string& extra_elements) {
  return "ply\nformat " + format + " 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
         "element face 1\nproperty list uchar int vertex_indices\n" + extra_elements + "end_header\n";
}

std::string binary_triangle() {
  std::string s;
  const float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  s.append(reinterpret_cast<const char*>(v), sizeof(v));
  s.push_back(3);
  const std::int32_t idx[3] = {0, 1, 2};
  s.append(reinterpret_cast<const char*>(idx), sizeof(idx));
  return s;
}

TEST_F(MeshIo, HugeDeclaredCountsFailAtOnce) {
  const std::string tri = binary_triangle(), ascii = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  // An extra element the reader skips, 10^12 entries without properties: used to loop for hours.
  expect_input_error([&] { read_mesh(write("a.ply", ply_head("binary_little_endian", "element junk 1000000000000\n") + tri)); },
                     "element 'junk' declares 1000000000000 entries that hold no values");
  expect_input_error([&] { read_mesh(write("b.ply", ply_head("ascii", "element junk 1000000000000\n") + ascii)); },
                     "hold no values");
  // With a property: 10^12 entries of at least one byte (binary) or two (text) cannot follow.
  expect_input_error(
      [&] { read_mesh(write("c.ply", ply_head("binary_little_endian", "element junk 1000000000000\nproperty uchar q\n") + tri)); },
      "line 9: element 'junk' declares 1000000000000 entries of at least 1 bytes each, but only 12 bytes");
  expect_input_error(
      [&] { read_mesh(write("d.ply", ply_head("ascii", "element junk 1000000000000\nproperty list uint int q\n") + ascii)); },
      "element 'junk' declares 1000000000000 entries of at least 2 bytes each");
  // The same for the elements the reader keeps.
  const std::string many_faces = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                                 "property float y\nproperty float z\nelement face 100000000\n"
                                 "property list uchar int vertex_indices\nend_header\n";
  expect_input_error([&] { read_mesh(write("e.ply", many_faces + tri)); }, "element 'face' declares 100000000 entries");
  expect_input_error([&] { read_mesh(write("f.ply", "ply\nformat ascii 1.0\nelement vertex 1000000000000\nproperty float x\n"
                                                    "property float y\nproperty float z\nelement face 0\n"
                                                    "property list uchar int vertex_indices\nend_header\n")); },
                     "'vertex' count 1000000000000 too large");
  expect_input_error([&] { read_mesh(write("g.off", "OFF\n100000000 1 0\n0 0 0\n")); },
                     "line 2: the header's vertex count declares 100000000 entries of at least 6 bytes");
  expect_input_error([&] { read_mesh(write("h.off", "OFF\n3 99999999 0\n" + ascii.substr(0, 18) + "3 0 1 2\n")); },
                     "face count declares 99999999 entries");
  // A binary list whose length runs past the data.
  std::string bad = tri;
  bad[36] = char(200);
  expect_input_error([&] { read_mesh(write("i.ply", ply_head("binary_little_endian", "") + bad)); },
                     "binary data ends inside 'face' element 0 of 1");
}

TEST_F(MeshIo, NonFiniteCoordinatesAreRefusedByEveryReader) {
  expect_input_error([&] { read_mesh(write("a.off", "OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n")); },
                     "line 4: vertex 1: non-finite coordinate nan");
  expect_input_error([&] { read_mesh(write("b.obj", "v 0 0 0\nv 1 0 0\nv 0 inf 0\nf 1 2 3\n")); },
                     "line 3: vertex 3: non-finite coordinate inf");  // OBJ counts vertices from 1
  expect_input_error([&] { read_mesh(write("c.ply", ply_head("ascii", "") + "0 0 0\n1 0 -inf\n0 1 0\n3 0 1 2\n")); },
                     "vertex 1: non-finite coordinate -inf");
  std::string tri = binary_triangle();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(&tri[8], &nan, 4);
  expect_input_error([&] { read_mesh(write("d.ply", ply_head("binary_little_endian", "") + tri)); },
                     "vertex 0: non-finite coordinate");
  expect_input_error([&] { read_mesh(write("e.off", "OFF\n3 1 0\n0 0 0\n1 1e400 0\n0 1 0\n3 0 1 2\n")); }, "bad number '1e400'");
}

TEST_F(MeshIo, PlyAsciiValuesMustFitTheirType) {
  const std::string v = "0 0 0\n1 0 0\n0 1 0\n";
  expect_input_error([&] { read_mesh(write("a.ply", ply_head("ascii", "") + v + "300 0 1 2\n")); }, "bad value '300'");
  expect_input_error([&] { read_mesh(write("b.ply", ply_head("ascii", "") + v + "3 0 1 99999999999\n")); },
                     "bad value '99999999999'");
}

TEST_F(MeshIo, PlyTriangleStripsAreReadAsTriangles) {
  // Strip 0 1 2 3 4 4 -1 4 3 5: triangles (0 1 2), (2 1 3), (2 3 4), none for (3 4 4) (a repeated index only
  // stitches strips), then after the restart (4 3 5).
  const std::string v = "0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 2 0\n2 2 0\n";
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\nproperty float z\n"
                           "element tristrips 1\nproperty list int int vertex_indices\nend_header\n";
  Mesh m = read_mesh(write("a.ply", head + v + "10 0 1 2 3 4 4 -1 4 3 5\n"));
  ASSERT_EQ(m.num_faces(), 4);
  EXPECT_EQ(m.F.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(m.F.row(1), Eigen::RowVector3i(2, 1, 3));
  EXPECT_EQ(m.F.row(2), Eigen::RowVector3i(2, 3, 4));
  EXPECT_EQ(m.F.row(3), Eigen::RowVector3i(4, 3, 5));
  EXPECT_NO_THROW(validate_mesh(m));
  // Binary, beside a face element.
  std::string bin = "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
                    "property double z\nelement face 1\nproperty list uchar uint vertex_indices\nelement tristrips 1\n"
                    "property list uint int vertex_indices\nend_header\n";
  const double xyz[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 1};
  bin.append(reinterpret_cast<const char*>(xyz), sizeof(xyz));
  bin.push_back(3);
  const std::uint32_t face[3] = {0, 1, 2};
  bin.append(reinterpret_cast<const char*>(face), sizeof(face));
  const std::uint32_t n = 4;
  const std::int32_t strip[4] = {1, 3, 2, -1};
  bin.append(reinterpret_cast<const char*>(&n), 4);
  bin.append(reinterpret_cast<const char*>(strip), sizeof(strip));
  m = read_mesh(write("b.ply", bin));
  ASSERT_EQ(m.num_faces(), 2);
  EXPECT_EQ(m.F.row(1), Eigen::RowVector3i(1, 3, 2));
  expect_input_error([&] { read_mesh(write("c.ply", head + v + "3 0 1 6\n")); },
                     "tristrips 0: index 6 out of range [0, 6) (-1 restarts a strip)");
  expect_input_error([&] { read_mesh(write("d.ply", head + v + "3 0 -2 1\n")); }, "index -2 out of range");
  expect_input_error(
      [&] {
        read_mesh(write("e.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                                 "property float z\nend_header\n0 0 0\n"));
      },
      "no 'face' element (nor 'tristrips' triangle strips)");
}

TEST_F(MeshIo, ObjErrorsQuoteIndicesAsWritten) {
  const std::string v3 = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  expect_input_error([&] { read_mesh(write("a.obj", v3 + "f 1 2 9\n")); },
                     "line 4: face: index 9 out of range (OBJ indices are 1-based; 3 vertices defined so far)");
  expect_input_error([&] { read_mesh(write("b.obj", v3 + "f 1 2 -9/1/1\n")); },
                     "face: index -9 out of range (a negative index counts back from the last vertex; 3 vertices");
  expect_input_error([&] { read_mesh(write("c.obj", "v 0 0 0\nf 1 2 3\nv 1 0 0\nv 0 1 0\n")); },
                     "line 2: face: index 2 out of range (OBJ indices are 1-based; 1 vertices defined so far)");
}

TEST_F(MeshIo, DevicesAreNotRead) {
  // /dev/zero would otherwise be read without end.
  fs::create_symlink("/dev/zero", dir_ / "zero.off");
  expect_input_error([&] { read_mesh(path("zero.off")); }, "not a regular file");
}

// ---------------------------------------------------------------- STL
// STL keeps corners, not vertices: a mesh comes back with its vertices in order of first use by the faces. The
// reference renumbering is written here independently of the reader's welding.
Mesh first_use_order(const Mesh& m) {
  std::vector<int> id(m.num_vertices(), -1);
  std::vector<int> order;
  Mesh r = m;
  for (int f = 0; f < m.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      int& v = id[m.F(f, k)];
      if (v < 0) v = static_cast<int>(order.size()), order.push_back(m.F(f, k));
      r.F(f, k) = v;
    }
  r.V.resize(static_cast<Eigen::Index>(order.size()), 3);
  for (std::size_t i = 0; i < order.size(); ++i) r.V.row(static_cast<Eigen::Index>(i)) = m.V.row(order[i]);
  return r;
}

// Each coordinate rounded to the nearest float, as binary STL stores it.
Mesh rounded_to_float(Mesh m) {
  for (Eigen::Index i = 0; i < m.V.size(); ++i) m.V.data()[i] = static_cast<float>(m.V.data()[i]);
  return m;
}

// A binary STL: the 80-byte header (padded with zero bytes), the count, then per triangle a zero normal, the nine
// corner coordinates and a zero attribute. `count` overrides the declared count.
std::string binary_stl(const std::string& header, const std::vector<std::array<float, 9>>& tris, long long count = -1) {
  std::string s = header.substr(0, 80);
  s.resize(80, '\0');
  const auto n = static_cast<std::uint32_t>(count >= 0 ? count : static_cast<long long>(tris.size()));
  s.append(reinterpret_cast<const char*>(&n), 4);
  for (const auto& t : tris) {
    s.append(12, '\0');
    s.append(reinterpret_cast<const char*>(t.data()), sizeof(t));
    s.append(2, '\0');
  }
  return s;
}

// Two triangles on a unit square sharing the edge (1 0 0)-(0 1 0).
const std::vector<std::array<float, 9>> kSquare = {{0, 0, 0, 1, 0, 0, 0, 1, 0}, {1, 0, 0, 1, 1, 0, 0, 1, 0}};

std::string ascii_facet(const std::string& a, const std::string& b, const std::string& c) {
  return "facet normal 0 0 1\nouter loop\nvertex " + a + "\nvertex " + b + "\nvertex " + c + "\nendloop\nendfacet\n";
}

TEST_F(MeshIo, StlAsciiRoundTripIsExact) {
  const Mesh m = first_use_order(awkward_mesh());
  write_mesh(path("rt.stl"), m);  // ASCII by default
  EXPECT_EQ(slurp(path("rt.stl")).rfind("solid " + m.name + "\n", 0), 0u);  // the mesh's name, not the file's
  const Mesh r = read_mesh(path("rt.stl"));
  expect_same(m, r);
  EXPECT_EQ(r.name, "rt");
  write_mesh(path("again.stl"), r, {StlEncoding::Ascii});
  expect_same(m, read_mesh(path("again.stl")));
}

TEST_F(MeshIo, StlBinaryRoundTripIsExactForFloatsAndRoundsDoubles) {
  const Mesh m = first_use_order(awkward_mesh());
  const MeshWriteOptions binary{StlEncoding::Binary};
  write_mesh(path("b.stl"), m, binary);
  const std::string bytes = slurp(path("b.stl"));
  ASSERT_EQ(bytes.size(), 84u + 50u * static_cast<std::size_t>(m.num_faces()));
  EXPECT_NE(bytes.substr(0, 5), "solid");  // readers that look at the header alone would take it for ASCII
  // Doubles become their nearest floats (1e-300 becomes 0) and nothing else changes.
  const Mesh r = read_mesh(path("b.stl"));
  expect_same(rounded_to_float(m), r);
  // A mesh of floats comes back bit for bit.
  write_mesh(path("c.stl"), r, binary);
  expect_same(r, read_mesh(path("c.stl")));
  EXPECT_EQ(slurp(path("c.stl")), bytes);
}

TEST_F(MeshIo, StlWritesUnitNormalsAndKeepsFaceOrder) {
  Mesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 2, 0, 0, 0, 2, 0, 0, 0, 3;
  m.F.resize(2, 3);
  m.F << 0, 1, 2, 0, 3, 1;
  m.name = "two";
  write_mesh(path("n.stl"), m);
  const std::string s = slurp(path("n.stl"));
  EXPECT_NE(s.find("facet normal 0 0 1\n"), std::string::npos) << s;
  EXPECT_NE(s.find("facet normal 0 1 0\n"), std::string::npos) << s;  // (0 0 3) x (2 0 0) points along +y
  EXPECT_LT(s.find("vertex 0 0 3"), s.find("endsolid two"));
  expect_same(m, read_mesh(path("n.stl")));  // already in first-use order
}

TEST_F(MeshIo, StlWeldsCornersWithBitwiseEqualCoordinatesOnly) {
  // "1", "1.0", "1e0" and "+1" are the same double: one vertex. -0 and 0 are different bits: two vertices.
  // 0.1 and the next double after it: two vertices.
  const std::string tenth = fmt::format("{}", std::nextafter(0.1, 1.0));
  const std::string ascii = "solid w\n" + ascii_facet("0 0 0", "1 0 0", "0 1 0") +
                            ascii_facet("1.0 0 0", "1e0 1 0", "0 +1 0") + ascii_facet("0 -0 0", "1 0 0", "0 1 0") +
                            ascii_facet("0.1 5 0", tenth + " 5 0", "0 1 0") + "endsolid w\n";
  const Mesh m = read_mesh(write("w.stl", ascii));
  ASSERT_EQ(m.num_faces(), 4);
  ASSERT_EQ(m.num_vertices(), 7);
  EXPECT_EQ(m.F.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(m.F.row(1), Eigen::RowVector3i(1, 3, 2));
  EXPECT_EQ(m.F.row(2), Eigen::RowVector3i(4, 1, 2));
  EXPECT_TRUE(std::signbit(m.V(4, 1)));
  EXPECT_EQ(m.F.row(3), Eigen::RowVector3i(5, 6, 2));
  // Binary: the shared edge's corners become the same two vertices, in order of first appearance.
  const Mesh b = read_mesh(write("w2.stl", binary_stl("", kSquare)));
  ASSERT_EQ(b.num_vertices(), 4);
  EXPECT_EQ(b.F.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(b.F.row(1), Eigen::RowVector3i(1, 3, 2));
  EXPECT_EQ(b.V.row(3), Eigen::RowVector3d(1, 1, 0));
  // Vertices no face uses are not in a written STL; vertices at the same position come back as one.
  Mesh u = make_cylinder(2, 3, 1, 1);
  u.V.conservativeResize(u.num_vertices() + 1, 3);
  u.V.row(u.num_vertices() - 1) << 9, 9, 9;
  write_mesh(path("u.stl"), u);
  expect_same(first_use_order(make_cylinder(2, 3, 1, 1)), read_mesh(path("u.stl")));
}

TEST_F(MeshIo, StlBinaryIsDecidedBySizeNotByTheWordSolid) {
  // Many binary writers begin the header with "solid": the size 84 + 50 n decides.
  const Mesh m = read_mesh(write("s.stl", binary_stl("solid exported by a CAD tool", kSquare)));
  EXPECT_EQ(m.num_faces(), 2);
  EXPECT_EQ(m.num_vertices(), 4);
  // Cut short, the same file is neither: the message gives both readings.
  const std::string cut = binary_stl("solid exported by a CAD tool", kSquare).substr(0, 150);
  expect_input_error([&] { read_mesh(write("c.stl", cut)); },
                     "line 1: binary data in an ASCII STL (or a binary STL whose header begins with 'solid', but the "
                     "binary header declares 2 triangles, which take 84 + 50 * 2 = 184 bytes, but the file has 150 "
                     "bytes (a truncated file or a wrong count))");
  // ASCII with leading blanks, keywords in upper case and two solids.
  const std::string two = "  SOLID a\n" + ascii_facet("0 0 0", "1 0 0", "0 1 0") + "ENDSOLID a\nsolid b\n" +
                          ascii_facet("1 0 0", "1 1 0", "0 1 0") + "endsolid\n";
  const Mesh a = read_mesh(write("a.STL", two));
  EXPECT_EQ(a.num_faces(), 2);
  EXPECT_EQ(a.num_vertices(), 4);
}

TEST_F(MeshIo, StlBinaryMalformed) {
  const std::string good = binary_stl("", kSquare);
  expect_input_error([&] { read_mesh(write("t.stl", good.substr(0, 183))); },
                     "t.stl: not an ASCII STL (it does not begin with 'solid'), and the binary header declares 2 "
                     "triangles, which take 84 + 50 * 2 = 184 bytes, but the file has 183 bytes");
  expect_input_error([&] { read_mesh(write("x.stl", good + "x")); }, "but the file has 185 bytes");
  // A count of 2^32 - 1 in a small file is refused on the size, before anything is allocated.
  expect_input_error([&] { read_mesh(write("h.stl", binary_stl("", kSquare, 0xffffffffLL))); },
                     "declares 4294967295 triangles, which take 84 + 50 * 4294967295 = 214748364834 bytes");
  expect_input_error([&] { read_mesh(write("s.stl", "x y z")); },
                     "s.stl: 5 bytes, too short for a binary STL (84 bytes at least) and not an ASCII STL");
  expect_input_error([&] { read_mesh(write("z.stl", "")); }, "0 bytes, too short");
  expect_input_error([&] { read_mesh(write("e.stl", binary_stl("", {}))); }, "binary STL with 0 triangles");
  auto bad = kSquare;
  bad[1][4] = std::numeric_limits<float>::infinity();
  expect_input_error([&] { read_mesh(write("i.stl", binary_stl("", bad))); },
                     "i.stl: triangle 1 (byte 134): corner 1: non-finite coordinate inf");
  bad = kSquare;
  bad[0][6] = 0, bad[0][7] = 0;  // corner 2 on corner 0
  expect_input_error([&] { read_mesh(write("d.stl", binary_stl("", bad))); },
                     "d.stl: triangle 0 (byte 84): corners 0 and 2 are the same point (0, 0, 0): a degenerate "
                     "triangle");
}

TEST_F(MeshIo, StlAsciiMalformed) {
  const std::string f0 = ascii_facet("0 0 0", "1 0 0", "0 1 0");  // lines 2-8 after "solid s"
  auto stl = [&](const std::string& body) { return "solid s\n" + body; };
  expect_input_error([&] { read_mesh(write("a.stl", stl(f0))); },
                     "a.stl: line 8: file ends after 1 facets without 'endsolid'");
  expect_input_error([&] { read_mesh(write("b.stl", stl(f0.substr(0, 30)))); },
                     "b.stl: line 3: file ends inside facet 0 (expected 'vertex x y z')");
  expect_input_error([&] { read_mesh(write("c.stl", stl(ascii_facet("0 0 0", "1 zz 0", "0 1 0")))); },
                     "line 5: bad number 'zz' in 'vertex x y z'");
  expect_input_error([&] { read_mesh(write("d.stl", stl(ascii_facet("0 0 0", "1 0", "0 1 0")))); },
                     "line 5: expected 'vertex x y z', got 'vertex 1 0'");
  expect_input_error([&] { read_mesh(write("e.stl", stl(ascii_facet("0 0 0", "1 0 0", "0 1 0\nvertex 1 1 0")))); },
                     "line 7: facet 0: more than 3 corners (a facet has 3)");
  expect_input_error(
      [&] { read_mesh(write("f.stl", stl("facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\n"))); },
      "line 6: facet 0: 2 corners (a facet has 3)");
  expect_input_error([&] { read_mesh(write("g.stl", stl(f0 + "facet normal 0 0\n"))); },
                     "line 9: expected 'facet normal x y z', got 'facet normal 0 0'");
  expect_input_error([&] { read_mesh(write("h.stl", stl(f0 + "vertex 0 0 0\n"))); },
                     "line 9: expected 'facet normal nx ny nz' or 'endsolid', got 'vertex 0 0 0'");
  expect_input_error([&] { read_mesh(write("i.stl", stl(f0 + ascii_facet("0 0 0", "nan 0 0", "0 1 0")))); },
                     "line 12: facet 1: corner 1: non-finite coordinate nan");
  expect_input_error([&] { read_mesh(write("j.stl", stl(f0 + ascii_facet("0 0 0", "1 0 0", "1.0 0 0")))); },
                     "line 13: facet 1: corners 1 and 2 are the same point (1, 0, 0): a degenerate triangle");
  expect_input_error([&] { read_mesh(write("k.stl", stl("endsolid s\n"))); }, "line 2: no facets (an empty mesh)");
  expect_input_error([&] { read_mesh(write("l.stl", stl(f0 + "endsolid s\nfacet normal 0 0 1\n"))); },
                     "line 10: expected 'solid NAME', got 'facet normal 0 0 1'");
  expect_input_error([&] { read_mesh(write("m.stl", "solidify\n" + f0 + "endsolid\n")); },
                     "m.stl: not an ASCII STL (it does not begin with 'solid')");
  expect_input_error([&] { read_mesh(write("n.stl", stl(ascii_facet("0 0 0", "1 0 0", "0 1e400 0")))); },
                     "bad number '1e400'");
}

TEST_F(MeshIo, StlWriterRefusesWhatItsReaderWouldRefuse) {
  Mesh m = make_cylinder(2, 3, 1, 1);
  Mesh empty = m;
  empty.F.resize(0, 3);
  expect_input_error([&] { write_mesh(path("e.stl"), empty); },
                     "cannot write " + path("e.stl") + ": STL holds triangles only, and the mesh has no face");
  Mesh repeated = m;
  repeated.F(1, 2) = repeated.F(1, 0);
  expect_input_error([&] { write_mesh(path("r.stl"), repeated); },
                     "cannot write " + path("r.stl") + ": face 1: corners 0 and 2 are the same point");
  // Distinct doubles one float apart at most collapse in binary only.
  Mesh close = m;
  close.V.row(close.F(0, 1)) = close.V.row(close.F(0, 0));
  close.V(close.F(0, 1), 0) = std::nextafter(close.V(close.F(0, 0), 0), 10.0);
  EXPECT_NO_THROW(write_mesh(path("ok.stl"), close));
  expect_input_error([&] { write_mesh(path("c.stl"), close, {StlEncoding::Binary}); },
                     "cannot write " + path("c.stl") + ": face 0: corners 0 and 1 are the same point");
  expect_input_error([&] { write_mesh(path("c.stl"), close, {StlEncoding::Binary}); }, "once rounded to 32-bit floats");
  Mesh huge = m;
  huge.V(2, 1) = 1e300;
  EXPECT_NO_THROW(write_mesh(path("h_ascii.stl"), huge));
  expect_input_error([&] { write_mesh(path("h.stl"), huge, {StlEncoding::Binary}); },
                     "cannot write " + path("h.stl") + ": vertex 2: coordinate 1e+300 is beyond binary STL's 32-bit "
                     "floats");
  Mesh nan = m;
  nan.V(0, 0) = std::numeric_limits<double>::quiet_NaN();
  expect_input_error([&] { write_mesh(path("n.stl"), nan); }, "cannot write " + path("n.stl") + ": ");
  // Refused before a file is opened: nothing is left, not even a temporary.
  for (const auto& e : fs::directory_iterator(dir_)) {
    const std::string name = e.path().filename().string();
    EXPECT_TRUE(name == "ok.stl" || name == "h_ascii.stl") << name;
  }
}

}  // namespace
