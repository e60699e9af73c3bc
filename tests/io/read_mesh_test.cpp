// SPDX-License-Identifier: MIT
// read_mesh: real OFF models against an independent OFF parser, round trips through every format
// written by the test itself, welding, triangulation and the documented errors.
#include "io/io_test_util.h"

#include <hdm/core/error.h>
#include <hdm/io/read_mesh.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace hdm {
namespace {

using test::TempDir;

// ---- an independent OFF parser: header counts, vertices and faces as written ----
struct OffFile {
  size_t header_vertices = 0, header_faces = 0;
  std::vector<Vec3> vertices;
  std::vector<std::vector<int>> faces;
};

OffFile parse_off(const std::string& path) {
  std::ifstream in(path);
  std::string magic;
  in >> magic;
  EXPECT_EQ(magic, "OFF") << path;
  OffFile off;
  size_t edges = 0;
  in >> off.header_vertices >> off.header_faces >> edges;
  for (size_t v = 0; v < off.header_vertices; ++v) {
    double x, y, z;
    in >> x >> y >> z;
    off.vertices.emplace_back(x, y, z);
  }
  for (size_t f = 0; f < off.header_faces; ++f) {
    int k;
    in >> k;
    std::vector<int> face(k);
    for (int& i : face) in >> i;
    off.faces.push_back(face);
  }
  EXPECT_TRUE(in) << path << ": the test's OFF parser failed";
  return off;
}

// Triangle as three positions, rotated so the lexicographically smallest corner comes first
// (keeps the winding), for comparing meshes up to vertex numbering.
using PosTri = std::array<std::array<double, 3>, 3>;
std::vector<PosTri> canonical_triangles(const std::vector<Vec3>& vertices, const std::vector<Tri>& faces) {
  std::vector<PosTri> out;
  for (const Tri& f : faces) {
    PosTri t;
    for (int k = 0; k < 3; ++k) t[k] = {vertices[f[k]].x(), vertices[f[k]].y(), vertices[f[k]].z()};
    const int first = int(std::min_element(t.begin(), t.end()) - t.begin());
    std::rotate(t.begin(), t.begin() + first, t.end());
    out.push_back(t);
  }
  std::sort(out.begin(), out.end());
  return out;
}

class RealOff : public ::testing::TestWithParam<const char*> {};

TEST_P(RealOff, CountsAndGeometryMatchAnIndependentParser) {
  const std::string path = std::string(HDM_DATA_DIR) + "/" + GetParam();
  ASSERT_TRUE(std::filesystem::exists(path)) << path << " missing: run scripts/setup.sh";
  const OffFile off = parse_off(path);
  const TriangleMesh mesh = read_mesh(path);
  // These models use every vertex once, at distinct positions, and have only triangles.
  EXPECT_EQ(mesh.vertices.size(), off.header_vertices);
  ASSERT_EQ(mesh.faces.size(), off.header_faces);

  // Face f of the file is face f of the mesh with the same corners (positions to float precision),
  // and the induced map from file vertex to mesh vertex is one-to-one.
  std::vector<int> file_to_mesh(off.vertices.size(), -1), mesh_to_file(mesh.vertices.size(), -1);
  size_t bad = 0;
  for (size_t f = 0; f < off.faces.size(); ++f) {
    ASSERT_EQ(off.faces[f].size(), 3u);
    for (int k = 0; k < 3; ++k) {
      const int a = off.faces[f][k], b = mesh.faces[f][k];
      ASSERT_GE(b, 0);
      ASSERT_LT(size_t(b), mesh.vertices.size());
      const Vec3& p = off.vertices[a];
      const Vec3& q = mesh.vertices[b];
      for (int c = 0; c < 3; ++c) bad += std::abs(p[c] - q[c]) > 2e-7 * std::max(1.0, std::abs(p[c]));
      if (file_to_mesh[a] < 0) file_to_mesh[a] = b;
      if (mesh_to_file[b] < 0) mesh_to_file[b] = a;
      bad += file_to_mesh[a] != b || mesh_to_file[b] != a;
    }
  }
  EXPECT_EQ(bad, 0u);
  for (const Vec3& v : mesh.vertices) EXPECT_TRUE(v.allFinite());
}

INSTANTIATE_TEST_SUITE_P(DataMeshes, RealOff,
                         ::testing::Values("bunny00.off", "armadillo.off", "refined_elephant.off", "lion-head.off"));

// ---- round trips of a small mesh written by the test in every format ----

// An octahedron stretched to (1, 2, 3)·v: exact in float, no symmetry hides a permutation.
TriangleMesh small_mesh() {
  TriangleMesh m;
  for (const Vec3& v : test::octahedron_vertices()) m.vertices.push_back(v.cwiseProduct(Vec3(1, 2, 3)));
  m.faces = test::octahedron_faces();
  return m;
}

std::string to_obj(const TriangleMesh& m) {
  std::ostringstream s;
  s << "# test\n";
  for (const Vec3& v : m.vertices) s << "v " << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
  for (const Tri& f : m.faces) s << "f " << f[0] + 1 << ' ' << f[1] + 1 << ' ' << f[2] + 1 << '\n';
  return s.str();
}

std::string to_off(const TriangleMesh& m) {
  std::ostringstream s;
  s << "OFF\n" << m.vertices.size() << ' ' << m.faces.size() << " 0\n";
  for (const Vec3& v : m.vertices) s << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
  for (const Tri& f : m.faces) s << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
  return s.str();
}

std::string ply_header(const char* format, size_t nv, size_t nf) {
  std::ostringstream s;
  s << "ply\nformat " << format << " 1.0\nelement vertex " << nv
    << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << nf
    << "\nproperty list uchar int vertex_indices\nend_header\n";
  return s.str();
}

std::string to_ply_ascii(const TriangleMesh& m) {
  std::ostringstream s;
  s << ply_header("ascii", m.vertices.size(), m.faces.size());
  for (const Vec3& v : m.vertices) s << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
  for (const Tri& f : m.faces) s << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
  return s.str();
}

using test::put;

std::string to_ply_binary(const TriangleMesh& m, bool big) {
  std::string s = ply_header(big ? "binary_big_endian" : "binary_little_endian", m.vertices.size(), m.faces.size());
  for (const Vec3& v : m.vertices)
    for (int c = 0; c < 3; ++c) put(s, float(v[c]), big);
  for (const Tri& f : m.faces) {
    put(s, uint8_t{3});
    for (int32_t i : f) put(s, i, big);
  }
  return s;
}

std::string to_stl_ascii(const TriangleMesh& m) {
  std::ostringstream s;
  s << "solid test\n";
  for (const Tri& f : m.faces) {
    const Vec3 n = (m.vertices[f[1]] - m.vertices[f[0]]).cross(m.vertices[f[2]] - m.vertices[f[0]]).normalized();
    s << " facet normal " << n.x() << ' ' << n.y() << ' ' << n.z() << "\n  outer loop\n";
    for (int32_t i : f)
      s << "   vertex " << m.vertices[i].x() << ' ' << m.vertices[i].y() << ' ' << m.vertices[i].z() << '\n';
    s << "  endloop\n endfacet\n";
  }
  s << "endsolid test\n";
  return s.str();
}

std::string to_stl_binary(const TriangleMesh& m) {
  std::string s(80, ' ');
  put(s, uint32_t(m.faces.size()));
  for (const Tri& f : m.faces) {
    const Vec3 n = (m.vertices[f[1]] - m.vertices[f[0]]).cross(m.vertices[f[2]] - m.vertices[f[0]]).normalized();
    for (int c = 0; c < 3; ++c) put(s, float(n[c]));
    for (int32_t i : f)
      for (int c = 0; c < 3; ++c) put(s, float(m.vertices[i][c]));
    put(s, uint16_t{0});
  }
  return s;
}

struct Writer {
  const char* file;
  std::string (*write)(const TriangleMesh&);
};

class RoundTrip : public ::testing::TestWithParam<Writer> {};

TEST_P(RoundTrip, SameTrianglesAndWeldedVertices) {
  const TriangleMesh m = small_mesh();
  TempDir dir;
  const std::string path = dir.file(GetParam().file);
  test::write_text(path, GetParam().write(m));
  const TriangleMesh r = read_mesh(path);
  EXPECT_EQ(r.vertices.size(), m.vertices.size()) << "shared corners must be welded";
  EXPECT_EQ(canonical_triangles(r.vertices, r.faces), canonical_triangles(m.vertices, m.faces));
}

INSTANTIATE_TEST_SUITE_P(
    Formats, RoundTrip,
    ::testing::Values(Writer{"m.obj", to_obj}, Writer{"m.off", to_off}, Writer{"m_ascii.ply", to_ply_ascii},
                      Writer{"m_le.ply", [](const TriangleMesh& m) { return to_ply_binary(m, false); }},
                      Writer{"m_be.ply", [](const TriangleMesh& m) { return to_ply_binary(m, true); }},
                      Writer{"m_ascii.stl", to_stl_ascii}, Writer{"m_binary.stl", to_stl_binary}),
    [](const auto& info) {
      std::string name = info.param.file;
      std::replace(name.begin(), name.end(), '.', '_');
      return name;
    });

TEST(ReadMesh, DropsUnusedVertices) {
  TempDir dir;
  const std::string path = dir.file("unused.obj");
  test::write_text(path,
                   "v 9 9 9\nv 0 0 0\nv 1 0 0\nv 7 7 7\nv 0 1 0\nv 0 0 1\n"
                   "f 2 3 5\nf 2 5 6\nf 2 6 3\nf 3 6 5\n");
  const TriangleMesh r = read_mesh(path);
  ASSERT_EQ(r.vertices.size(), 4u);
  for (const Vec3& v : r.vertices) EXPECT_LE(v.norm(), 1.0) << "an unused vertex survived: " << v.transpose();
  for (const Tri& f : r.faces)
    for (int32_t i : f) EXPECT_LT(size_t(i), r.vertices.size());
}

TEST(ReadMesh, TriangulatesPolygons) {
  TempDir dir;
  const std::string path = dir.file("poly.obj");
  // A unit square (z = 0) and a convex pentagon (z = 1), both counter-clockwise seen from +z.
  test::write_text(path,
                   "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                   "v 0 0 1\nv 2 0 1\nv 3 1 1\nv 1 2 1\nv -1 1 1\n"
                   "f 1 2 3 4\nf 5 6 7 8 9\n");
  const TriangleMesh r = read_mesh(path);
  ASSERT_EQ(r.faces.size(), 2u + 3u);
  double area[2] = {0, 0};
  for (const Tri& f : r.faces) {
    const Vec3 n = (r.vertices[f[1]] - r.vertices[f[0]]).cross(r.vertices[f[2]] - r.vertices[f[0]]);
    EXPECT_GT(n.z(), 0) << "triangulation must keep the winding";
    const double z = r.vertices[f[0]].z();
    for (int32_t i : f) EXPECT_EQ(r.vertices[i].z(), z) << "a triangle mixes the two polygons";
    area[z > 0.5] += 0.5 * n.norm();
  }
  EXPECT_DOUBLE_EQ(area[0], 1.0);
  EXPECT_DOUBLE_EQ(area[1], 5.0);  // shoelace area of the pentagon: (0+2+5+3+0)/2
}

// ---- errors: type and path in the message ----

template <class E>
void expect_error(const std::string& path, const char* what) {
  try {
    read_mesh(path);
    ADD_FAILURE() << what << ": no exception for " << path;
  } catch (const E& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << what << ": " << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << what << ": wrong exception type: " << e.what();
  }
}

TEST(ReadMesh, MissingFileThrowsIoError) {
  TempDir dir;
  expect_error<IoError>(dir.file("does_not_exist.obj"), "missing file");
}

TEST(ReadMesh, EmptyFilesThrowIoError) {
  TempDir dir;
  for (const char* name : {"empty.obj", "empty.ply", "empty.off", "empty.stl"}) {
    test::write_text(dir.file(name), "");
    expect_error<IoError>(dir.file(name), name);
  }
}

TEST(ReadMesh, TruncatedPlyThrowsIoError) {
  TempDir dir;
  const TriangleMesh m = small_mesh();
  const std::string binary = to_ply_binary(m, false), ascii = to_ply_ascii(m);
  const size_t header = binary.find("end_header\n") + 11;
  // Cut inside the header (assimp alone loops forever there), the vertices and the faces.
  for (size_t cut : {size_t(20), header - 3, header + 5, header + 12 * 6 - 1, binary.size() - 1}) {
    const std::string path = dir.file("cut" + std::to_string(cut) + ".ply");
    test::write_text(path, binary.substr(0, cut));
    expect_error<IoError>(path, "truncated binary PLY");
  }
  const std::string path = dir.file("cut_ascii.ply");
  test::write_text(path, ascii.substr(0, ascii.size() - 12));
  expect_error<IoError>(path, "truncated ASCII PLY");
}

TEST(ReadMesh, NonFiniteCoordinateThrowsInvalidInput) {
  TempDir dir;
  TriangleMesh m = small_mesh();
  m.vertices[2].y() = std::numeric_limits<double>::quiet_NaN();
  const std::string ply = dir.file("nan.ply");
  test::write_text(ply, to_ply_binary(m, false));
  expect_error<InvalidInput>(ply, "NaN in binary PLY");
  m.vertices[2].y() = std::numeric_limits<double>::infinity();
  const std::string stl = dir.file("inf.stl");
  test::write_text(stl, to_stl_binary(m));
  expect_error<InvalidInput>(stl, "inf in binary STL");
}

TEST(ReadMesh, LinesOnlyThrowInvalidInput) {
  TempDir dir;
  const std::string path = dir.file("lines.obj");
  test::write_text(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3 1\n");
  expect_error<InvalidInput>(path, "lines only");
}

}  // namespace
}  // namespace hdm
