// SPDX-License-Identifier: MIT
// hdm's own OBJ, PLY, OFF and STL readers: the same sphere in three formats from CGAL's data,
// format variants against meshes written by the test, and the refusals (header claims, out-of-range
// ids, short facets, size limit), each naming the file and, for text, the line. Triangulation:
// polygon_triangulation_test.cpp.
#include "io/io_test_util.h"
#include "io/mesh_test_util.h"

#include <hdm/core/error.h>
#include <hdm/io/read_mesh.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace hdm {
namespace {

using test::TempDir;

using test::canonical;
using test::error_of;
using test::has;
using test::PosTri;
using test::put;

// The regular tetrahedron's corners and faces (outward, counter-clockwise).
const std::vector<Vec3> tet_v = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
const std::vector<Tri> tet_f = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
TriangleMesh tet() { return {tet_v, tet_f}; }

// ---- the same sphere in three formats (CGAL's data, extracted by scripts/setup.sh) ----

TEST(MeshReaders, CgalSphereIsTheSameInOffPlyAndStl) {
  const std::string dir = HDM_DATA_DIR;
  for (const char* f : {"sphere.off", "sphere.ply", "sphere.stl"})
    ASSERT_TRUE(std::filesystem::exists(dir + "/" + f)) << f << " missing: run scripts/setup.sh";
  const TriangleMesh off = read_mesh(dir + "/sphere.off"), ply = read_mesh(dir + "/sphere.ply"),
                     stl = read_mesh(dir + "/sphere.stl");
  EXPECT_EQ(off.faces.size(), 320u);  // the counts in the OFF and PLY headers
  EXPECT_EQ(off.vertices.size(), 162u);
  EXPECT_EQ(stl.vertices.size(), 162u) << "the STL's 960 corners weld to the sphere's 162 vertices";
  EXPECT_EQ(canonical(off), canonical(ply));
  EXPECT_EQ(canonical(off, true), canonical(stl)) << "binary STL stores float32";
}

TEST(MeshReaders, CgalFilesWithColoursCommentsAndExtraElements) {
  const std::string dir = HDM_DATA_DIR;
  auto area = [](const TriangleMesh& m) {
    double a = 0;
    for (const Tri& f : m.faces)
      a += 0.5 * (m.vertices[f[1]] - m.vertices[f[0]]).cross(m.vertices[f[2]] - m.vertices[f[0]]).norm();
    return a;
  };
  // COFF with blank lines and '#' comments after the colours: three triangles and a pentagon
  // (three triangles) tiling the square [-1, 1]² in the plane z = 0.
  const TriangleMesh coff = read_mesh(dir + "/mesh_with_colors.off");
  EXPECT_EQ(coff.faces.size(), 3u + 3u);
  for (const Vec3& v : coff.vertices) EXPECT_EQ(v.z(), 0.0);
  EXPECT_NEAR(area(coff), 4.0, 1e-12);
  // A cube with two triangles and five quads: 12 triangles with the cube's area (6 faces of 2x2).
  const TriangleMesh cube = read_mesh(dir + "/cube_poly.off");
  ASSERT_EQ(cube.faces.size(), 2u + 5u * 2u);
  EXPECT_NEAR(area(cube), 24.0, 1e-12);
  // ASCII PLY with normals, colours, ids, per-face colours and labels, and an edge element after faces.
  const TriangleMesh tetra = read_mesh(dir + "/colored_tetra.ply");
  EXPECT_EQ(tetra.faces.size(), 4u);
  EXPECT_EQ(tetra.vertices.size(), 4u);
}

// ---- format variants, against the tetrahedron written by the test ----

TEST(MeshReaders, PlyVariants) {
  const TriangleMesh t = tet();
  for (bool big : {false, true}) {
    // double coordinates in the order z y x, extra scalar and list properties, uint16 counts,
    // the face list named vertex_index, an element after the faces.
    std::string s = std::string("ply\r\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\r\ncomment test\r\nobj_info x\r\nelement vertex 4\r\nproperty double z\r\nproperty uchar "
                    "red\r\nproperty double y\r\nproperty list uchar float uv\r\nproperty double x\r\nelement face "
                    "4\r\nproperty list ushort uint vertex_index\r\nproperty int label\r\nelement edge 2\r\nproperty "
                    "int a\r\nproperty int b\r\nend_header\r\n";
    for (const Vec3& v : tet_v) {
      put(s, v.z(), big);
      put(s, uint8_t{7});
      put(s, v.y(), big);
      put(s, uint8_t{2});
      put(s, 0.5f, big);
      put(s, 0.25f, big);
      put(s, v.x(), big);
    }
    for (const Tri& f : tet_f) {
      put(s, uint16_t{3}, big);
      for (int32_t i : f) put(s, uint32_t(i), big);
      put(s, int32_t{-1}, big);
    }
    for (int k = 0; k < 4; ++k) put(s, int32_t{k}, big);
    const TriangleMesh r = read_mesh_from_memory(s, big ? "be.ply" : "le.ply");
    EXPECT_EQ(canonical(r), canonical(t)) << (big ? "big" : "little") << " endian";
  }
  // ASCII with a quad split into two triangles of the right winding.
  const std::string ascii =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";
  const TriangleMesh q = read_mesh_from_memory(ascii, "quad.ply");
  ASSERT_EQ(q.faces.size(), 2u);
  for (const Tri& f : q.faces)
    EXPECT_GT((q.vertices[f[1]] - q.vertices[f[0]]).cross(q.vertices[f[2]] - q.vertices[f[0]]).z(), 0);
}

TEST(MeshReaders, OffVariants) {
  const std::vector<PosTri> want = canonical(tet());
  // counts on the keyword's line, comments, trailing face colours
  EXPECT_EQ(canonical(read_mesh_from_memory("OFF 4 4 0 # counts\n0 0 0\n1 0 0 # a comment\n0 1 0#no space\n0 0 1\n"
                                            "3 0 2 1 255 0 0\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
                                            "a.off")),
            want);
  // no keyword; NOFF normals; 4OFF homogeneous coordinates (x/w)
  EXPECT_EQ(canonical(read_mesh_from_memory("4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
                                            "b.off")),
            want);
  EXPECT_EQ(canonical(read_mesh_from_memory("NOFF\n4 4 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n0 0 1 0 0 1\n"
                                            "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
                                            "c.off")),
            want);
  EXPECT_EQ(canonical(read_mesh_from_memory("4OFF\n4 4 0\n0 0 0 2\n2 0 0 2\n0 4 0 4\n0 0 0.5 0.5\n"
                                            "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
                                            "d.off")),
            want);
  // A face of ten corners (assimp 5.2 dropped faces of more than nine): a regular decagon, 8 triangles.
  std::ostringstream s;
  s << "OFF\n10 1 0\n";
  for (int k = 0; k < 10; ++k)
    s << std::cos(2 * std::numbers::pi * k / 10) << ' ' << std::sin(2 * std::numbers::pi * k / 10) << " 0\n";
  s << "10 0 1 2 3 4 5 6 7 8 9\n";
  EXPECT_EQ(read_mesh_from_memory(s.str(), "decagon.off").faces.size(), 8u);
}

TEST(MeshReaders, ObjVariants) {
  const std::vector<PosTri> want = canonical(tet());
  // v/vt/vn corners, negative (relative) indices, a continued line, comments, groups and materials.
  const std::string obj =
      "# tetrahedron\nmtllib t.mtl\no t\nv 0 0 0\nv 1 0 0 1.0\nv 0 1 0 0.5 0.5 0.5\nv 0 0 1\nvt 0 0\nvn 0 0 1\n"
      "g side\nusemtl red\ns 1\nf 1/1/1 3/1/1 2/1/1\nf 1//1 2//1 4//1\nf -4/1 -1/1 \\\n -2/1\nf 2 3 4 # last\n";
  EXPECT_EQ(canonical(read_mesh_from_memory(obj, "t.obj")), want);
  // Same vertex listed twice: welded.
  const TriangleMesh w = read_mesh_from_memory("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 0 0\nf 1 2 3\nf 1 3 4\n", "w.obj");
  EXPECT_EQ(w.vertices.size(), 3u);
}

// Counts of the mesh as read, each computed here: edges by their number of faces, and the
// components through shared edges.
struct EdgeCounts {
  size_t vertices = 0, edges = 0, boundary = 0, manifold = 0, non_manifold = 0, components = 0;
  long euler() const { return long(vertices) - long(edges); }  // + faces by the caller
};
EdgeCounts count_edges(const TriangleMesh& m) {
  std::vector<std::array<int32_t, 3>> e;  // (a, b, face), a < b
  for (size_t f = 0; f < m.faces.size(); ++f)
    for (int k = 0; k < 3; ++k)
      e.push_back({std::min(m.faces[f][k], m.faces[f][(k + 1) % 3]), std::max(m.faces[f][k], m.faces[f][(k + 1) % 3]),
                   int32_t(f)});
  std::sort(e.begin(), e.end());
  std::vector<int32_t> parent(m.faces.size());
  for (size_t f = 0; f < parent.size(); ++f) parent[f] = int32_t(f);
  auto root = [&](int32_t f) {
    while (parent[f] != f) f = parent[f];
    return f;
  };
  EdgeCounts c;
  c.vertices = m.vertices.size();
  for (size_t i = 0; i < e.size();) {
    size_t j = i;
    while (j < e.size() && e[j][0] == e[i][0] && e[j][1] == e[i][1]) ++j;
    ++c.edges;
    (j - i == 1 ? c.boundary : j - i == 2 ? c.manifold : c.non_manifold)++;
    for (size_t k = i + 1; k < j; ++k) parent[root(e[k][2])] = root(e[i][2]);
    i = j;
  }
  for (size_t f = 0; f < parent.size(); ++f) c.components += root(int32_t(f)) == int32_t(f);
  return c;
}

// A closed tetrahedron on the edge (0,0,0)-(0,0,1), apex towards +x (side +1) or -x (side -1),
// written as OFF vertices and faces starting at vertex id @p base.
void tet_on_edge(std::ostringstream& v, std::ostringstream& f, int base, double side) {
  v << "0 0 0\n0 0 1\n" << side << " 0.5 0.5\n" << side << " -0.5 0.5\n";
  const int a = base, b = base + 1, c = base + 2, d = base + 3;
  // Outward for side +1; mirrored (reversed) for side -1.
  const int faces[4][3] = {{a, b, c}, {a, d, b}, {a, c, d}, {b, d, c}};
  for (const auto& t : faces)
    if (side > 0)
      f << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
    else
      f << "3 " << t[0] << ' ' << t[2] << ' ' << t[1] << '\n';
}

// Two closed shapes that touch along an edge, each written with its own vertices (as
// diplodocus.off of libcgal-demo writes two vertex pairs): welding the equal positions would put
// four faces on the shared edge, and repair could only split it arbitrarily. The reader keeps the
// pairing the file wrote: two closed tetrahedra, every edge on two faces, Euler characteristic 4.
TEST(MeshReaders, WeldingKeepsTheEdgePairingTheFileWrote) {
  {
    std::ostringstream v, f;
    tet_on_edge(v, f, 0, 1);
    tet_on_edge(v, f, 4, -1);
    const TriangleMesh m = read_mesh_from_memory("OFF\n8 8 0\n" + v.str() + f.str(), "two_tets.off");
    const EdgeCounts c = count_edges(m);
    EXPECT_EQ(c.non_manifold, 0u);
    EXPECT_EQ(c.boundary, 0u);
    EXPECT_EQ(c.manifold, 12u);
    EXPECT_EQ(c.components, 2u);
    EXPECT_EQ(c.euler() + long(m.faces.size()), 4) << "two spheres";
    EXPECT_EQ(m.vertices.size(), 8u) << "no vertex welded: each tetrahedron keeps its own";
  }
  {
    // The same, the second tetrahedron sharing the file's vertex 0 and repeating only (0,0,1): a
    // surface pinched at vertex 0, as the file says, every edge still on two faces.
    std::ostringstream v, f;
    tet_on_edge(v, f, 0, 1);
    std::ostringstream v2, f2;
    tet_on_edge(v2, f2, 4, -1);
    std::string faces = f2.str();
    for (size_t at = 0; (at = faces.find(" 4", at)) != std::string::npos;) faces.replace(at, 2, " 0");
    const std::string verts = v.str() + "0 0 1\n-1 0.5 0.5\n-1 -0.5 0.5\n";
    // The second tetrahedron's ids 5, 6, 7 become 4, 5, 6.
    for (char& ch : faces)
      if (ch >= '5' && ch <= '7') --ch;
    const TriangleMesh m = read_mesh_from_memory("OFF\n7 8 0\n" + verts + f.str() + faces, "pinched.off");
    const EdgeCounts c = count_edges(m);
    EXPECT_EQ(c.non_manifold, 0u);
    EXPECT_EQ(c.boundary, 0u);
    EXPECT_EQ(c.manifold, 12u);
    EXPECT_EQ(c.components, 2u);
    EXPECT_EQ(m.vertices.size(), 7u);
  }
  {
    // A welded copy the file needs: an octahedron whose top vertex is written twice, one half of
    // its fan on each copy. Welding closes it (the file's own ids leave four boundary edges).
    const std::string oct =
        "OFF\n7 8 0\n1 0 0\n0 1 0\n-1 0 0\n0 -1 0\n0 0 1\n0 0 -1\n0 0 1\n"
        "3 0 1 4\n3 1 2 4\n3 2 3 6\n3 3 0 6\n3 1 0 5\n3 2 1 5\n3 3 2 5\n3 0 3 5\n";
    const TriangleMesh m = read_mesh_from_memory(oct, "octahedron.off");
    const EdgeCounts c = count_edges(m);
    EXPECT_EQ(m.vertices.size(), 6u);
    EXPECT_EQ(c.boundary, 0u);
    EXPECT_EQ(c.manifold, 12u);
    EXPECT_EQ(c.euler() + long(m.faces.size()), 2);
  }
  {
    // A file that is itself non-manifold (three faces on one edge, by its own ids) is read as
    // written and left to repair; so is an STL soup whose welding makes such an edge.
    const std::string fin = "OFF\n5 3 0\n0 0 0\n0 0 1\n1 0 0\n-1 0 0\n0 1 0\n3 0 1 2\n3 1 0 3\n3 0 1 4\n";
    EXPECT_EQ(count_edges(read_mesh_from_memory(fin, "fins.off")).non_manifold, 1u);
    const std::string stl =
        "solid s\n"
        "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 1 0 0\nendloop\nendfacet\n"
        "facet normal 0 0 0\nouter loop\nvertex 0 0 1\nvertex 0 0 0\nvertex -1 0 0\nendloop\nendfacet\n"
        "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 0 1 0\nendloop\nendfacet\n"
        "endsolid s\n";
    const TriangleMesh s = read_mesh_from_memory(stl, "fins.stl");
    EXPECT_EQ(s.vertices.size(), 5u);
    EXPECT_EQ(count_edges(s).non_manifold, 1u);
  }
}

TEST(MeshReaders, StlVariants) {
  const TriangleMesh t = tet();
  // Binary STL whose header starts with "solid" (as some exporters write): the exact size decides.
  std::string bin = "solid but binary";
  bin.resize(80, ' ');
  put(bin, uint32_t(4));
  for (const Tri& f : tet_f) {
    for (int c = 0; c < 3; ++c) put(bin, 0.0f);
    for (int32_t i : f)
      for (int c = 0; c < 3; ++c) put(bin, float(tet_v[i][c]));
    put(bin, uint16_t{0});
  }
  EXPECT_EQ(canonical(read_mesh_from_memory(bin, "solid_header.stl")), canonical(t));
  // ... with two bytes of padding after the records (still binary: it holds control bytes), and cut.
  EXPECT_EQ(canonical(read_mesh_from_memory(bin + "\n\n", "padded.stl")), canonical(t));
  EXPECT_TRUE(has(error_of<IoError>(bin.substr(0, bin.size() - 10), "cut.stl"),
                  "cut.stl: the binary STL header claims 4 triangles"));
  // Two ASCII solids, upper-case keywords in the second.
  std::ostringstream s;
  for (int solid = 0; solid < 2; ++solid) {
    s << (solid ? "SOLID B\n" : "solid a\n");
    for (int k = solid * 2; k < solid * 2 + 2; ++k) {
      s << (solid ? "FACET NORMAL 0 0 0\nOUTER LOOP\n" : "facet normal 0 0 0\n  outer loop\n");
      for (int32_t i : tet_f[k])
        s << (solid ? "VERTEX " : "    vertex ") << tet_v[i].x() << ' ' << tet_v[i].y() << ' ' << tet_v[i].z() << '\n';
      s << (solid ? "ENDLOOP\nENDFACET\n" : "  endloop\nendfacet\n");
    }
    s << (solid ? "ENDSOLID B\n" : "endsolid a\n");
  }
  EXPECT_EQ(canonical(read_mesh_from_memory(s.str(), "two.stl")), canonical(t));
}

TEST(MeshReaders, EveryCoordinateIsRoundedToFloat) {
  // A 20 x 20 grid whose coordinates are small integers plus 2^-30: exact in double, below half a
  // float ulp above 1, so float rounding gives the integers back exactly. (GCC 12's vectorizer once
  // dropped the rounding in release builds for two coordinates of three.)
  const double tiny = std::ldexp(1.0, -30);
  std::ostringstream s;
  s.precision(17);
  s << "OFF\n400 722 0\n";
  for (int j = 0; j < 20; ++j)
    for (int i = 0; i < 20; ++i)
      s << 1 + i + tiny << ' ' << 1 + j + tiny << ' ' << 1 + (i * 7 + j * 3) % 5 + tiny << '\n';
  for (int j = 0; j + 1 < 20; ++j)
    for (int i = 0; i + 1 < 20; ++i) {
      const int v = 20 * j + i;
      s << "3 " << v << ' ' << v + 1 << ' ' << v + 21 << "\n3 " << v << ' ' << v + 21 << ' ' << v + 20 << '\n';
    }
  const TriangleMesh m = read_mesh_from_memory(s.str(), "grid.off");
  ASSERT_EQ(m.vertices.size(), 400u);
  int unrounded = 0;
  for (const Vec3& p : m.vertices)
    for (int c = 0; c < 3; ++c) unrounded += p[c] != std::round(p[c]);
  EXPECT_EQ(unrounded, 0) << "coordinates not rounded to float";
}

// ---- refusals ----

TEST(MeshReaders, HeadersClaimingMoreThanTheFileHoldsAreRefused) {
  // An OFF header claiming 5 billion faces: assimp 5.2 allocated 11 GB for it.
  const std::string off = "OFF\n4 4999999999 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 3 1\n3 0 2 3";
  EXPECT_TRUE(
      has(error_of<IoError>(off, "claims.off"), "claims 4 vertices and 4,999,999,999 faces, but only 47 bytes"));
  const std::string ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 2147483647\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
      "end_header\n" +
      std::string(40, '\0');
  EXPECT_TRUE(has(error_of<IoError>(ply, "claims.ply"), "claims 2,147,483,647 vertex elements of at least 12 bytes"));
  std::string stl(80, ' ');
  put(stl, uint32_t(0xFFFFFFFF));
  stl += std::string(50, '\0');
  EXPECT_TRUE(has(error_of<IoError>(stl, "claims.stl"), "claims 4,294,967,295 triangles"));
  // A list count beyond the end of the file.
  std::string list =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list int int vertex_indices\nend_header\n";
  list += std::string(36, '\0');
  put(list, int32_t(1) << 30);
  put(list, int32_t{0});
  EXPECT_TRUE(has(error_of<IoError>(list, "list.ply"), "more than the rest of the file can hold"));
}

TEST(MeshReaders, BadIndicesAndShortFacetsNameTheLine) {
  // assimp 5.2 clamped an out-of-range OFF index to the last vertex.
  EXPECT_TRUE(has(error_of<IoError>("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n", "range.off"),
                  "range.off:6: face 0 refers to vertex 7, the file has 3 vertices"));
  EXPECT_TRUE(has(error_of<IoError>("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n", "range.obj"),
                  "range.obj:5: face refers to vertex 9, the file has 3 vertices"));
  EXPECT_TRUE(has(error_of<IoError>("v 0 0 0\nf 0 1 1\n", "zero.obj"), "zero.obj:2:"));
  EXPECT_TRUE(has(error_of<IoError>("v 0 0 0\nf -2 1 1\n", "back.obj"), "back.obj:2:"));
  EXPECT_TRUE(has(error_of<IoError>("v 0 0\n", "short.obj"), "short.obj:1: vertex 0 has 2 coordinates"));
  // assimp 5.2 dropped the fourth vertex of this facet without a word.
  const std::string stl =
      "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
      "vertex 9 9 9\nendloop\nendfacet\nendsolid t\n";
  EXPECT_TRUE(has(error_of<IoError>(stl, "four.stl"), "four.stl:7: facet 0 has more than 3 vertices"));
  EXPECT_TRUE(has(error_of<IoError>("solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nendloop\n", "two.stl"),
                  "two.stl:5: facet 0 has 1 vertices, expected 3"));
  EXPECT_TRUE(
      has(error_of<IoError>("solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n", "cut.stl"), "truncated"));
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n";
  EXPECT_TRUE(has(error_of<IoError>(ply, "range.ply"), "face 0 refers to vertex 3, the file has 3 vertices"));
  EXPECT_TRUE(has(error_of<IoError>("ply\nformat ascii 1.0\nelement vertex 3\n", "noend.ply"), "no end_header"));
  EXPECT_TRUE(has(error_of<InvalidInput>("OFF\n3 1 0\n0 0 0\n1 0 0\nnan 1 0\n3 0 1 2\n", "nan.off"),
                  "vertex 2 has a non-finite coordinate"));
  EXPECT_TRUE(has(error_of<InvalidInput>("v 0 0 0\nv 1 0 0\nl 1 2\n", "lines.obj"),
                  "lines.obj: holds no triangles: 1 line element (2 vertices)"));
}

TEST(MeshReaders, SizeLimitIsCheckedBeforeReading) {
  TempDir dir;
  const std::string path = dir.file("big.off");
  test::write_text(path, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  MeshReadOptions small;
  small.max_file_bytes = 16;
  try {
    read_mesh(path, small);
    ADD_FAILURE() << "no exception";
  } catch (const IoError& e) {
    EXPECT_TRUE(has(e.what(), path + ": 36 bytes, more than the input limit of 16 bytes")) << e.what();
  }
  EXPECT_EQ(read_mesh(path).faces.size(), 1u);  // the default limit (1 GiB) lets it through
  const std::vector<uint8_t> bytes = test::read_bytes(path);
  EXPECT_EQ(canonical(read_mesh_from_memory(std::string(bytes.begin(), bytes.end()), "big.off")),
            canonical(read_mesh(path)));
}

}  // namespace
}  // namespace hdm
