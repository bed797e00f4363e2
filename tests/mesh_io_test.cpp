// Mesh file formats: exact round trips, the accepted variants of each format, and strict rejection of bad files.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

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
  for (const char* ext : {".off", ".ply", ".obj"}) {
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
  expect_input_error([&] { read_mesh(write("a.stl", "solid")); }, "unknown mesh extension '.stl'");
  expect_input_error([&] { write_mesh(path("a.stl"), make_cylinder(2, 3, 1, 1)); }, "unknown mesh extension");
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

}  // namespace
