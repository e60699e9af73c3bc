// SPDX-License-Identifier: MIT
// What other readers read, against meshes written here: PLY header lines of other programs
// (skipped with a warning), PLY triangle strips (against the triangles worked out by hand), OBJ
// in UTF-16 (against its UTF-8 twin, encoded here), OBJ points and lines (skipped with one
// warning), and files without an extension (recognised by their content).
#include "io/io_test_util.h"
#include "io/mesh_test_util.h"

#include <hdm/core/error.h>
#include <hdm/io/read_mesh.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

namespace hdm {
namespace {

using test::canonical;
using test::error_of;
using test::has;
using test::put;

std::string ply_header(const char* format, const std::string& extra_line, const std::string& elements) {
  return std::string("ply\nformat ") + format + " 1.0\n" + extra_line +
         "element vertex 6\nproperty float x\nproperty float y\nproperty float z\n" + elements + "end_header\n";
}

// Six vertices on a 3 x 2 grid in z = 0, vertex i at (i / 2, i % 2): 0 (0,0), 1 (0,1), 2 (1,0),
// 3 (1,1), 4 (2,0), 5 (2,1).
const std::vector<Vec3> grid = {Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(2, 0, 0), Vec3(2, 1, 0)};
std::string grid_ascii() {
  std::string s;
  for (const Vec3& v : grid) s += std::to_string(int(v.x())) + " " + std::to_string(int(v.y())) + " 0\n";
  return s;
}
// The strip 1 0 3 2 5 4 worked out by hand: (1 0 3), then every other triangle turned around
// ((3 0 2) for 0 3 2), (3 2 5), (5 2 4): all counter-clockwise seen from +z.
std::string strip_triangles_obj() {
  std::string s;
  for (const Vec3& v : grid) s += "v " + std::to_string(int(v.x())) + " " + std::to_string(int(v.y())) + " 0\n";
  return s + "f 2 1 4\nf 4 1 3\nf 4 3 6\nf 6 3 5\n";
}

TEST(MeshReaders, PlyHeaderLinesOfOtherProgramsAreSkippedWithAWarning) {
  const std::string faces = "element face 2\nproperty list uchar int vertex_indices\n";
  const std::string body = grid_ascii() + "4 1 0 2 3\n3 3 2 5\n";
  const TriangleMesh plain = read_mesh_from_memory(ply_header("ascii", "", faces) + body, "plain.ply");
  MeshReadReport report;
  const TriangleMesh junk = read_mesh_from_memory(
      ply_header("ascii", "Created by Blender3D 247 - www.blender.org, source file: \n", faces) + body, "junk.ply", {},
      &report);
  EXPECT_EQ(canonical(junk), canonical(plain));
  EXPECT_EQ(plain.faces.size(), 3u);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_TRUE(has(report.warnings[0], "junk.ply:3: skipped the PLY header line \"Created by Blender3D 247...\""))
      << report.warnings[0];
  // Seven such lines: five named, the rest counted.
  std::string many;
  for (int k = 0; k < 7; ++k) many += "x" + std::to_string(k) + " y\n";
  report.warnings.clear();
  EXPECT_EQ(canonical(read_mesh_from_memory(ply_header("ascii", many, faces) + body, "many.ply", {}, &report)),
            canonical(plain));
  ASSERT_EQ(report.warnings.size(), 6u);
  EXPECT_TRUE(has(report.warnings[4], "many.ply:7: skipped the PLY header line \"x4 y\""));
  EXPECT_TRUE(has(report.warnings[5], "many.ply: skipped 2 more PLY header lines"));
  // A keyword line that is malformed is still an error.
  EXPECT_TRUE(has(error_of<IoError>(ply_header("ascii", "element\n", faces) + body, "bad.ply"),
                  "bad.ply:3: malformed PLY header line"));
}

TEST(MeshReaders, PlyTriangleStripsAreReadAsTheirTriangles) {
  const auto want = canonical(read_mesh_from_memory(strip_triangles_obj(), "by_hand.obj"));
  ASSERT_EQ(want.size(), 4u);
  const std::string strips = "element tristrips 1\nproperty list int int vertex_indices\n";
  // One strip; the same with a restart (-1); two strips joined by triangles that repeat a corner.
  for (const std::string list : {"6 1 0 3 2 5 4", "9 1 0 3 2 -1 3 2 5 4", "10 1 0 3 2 2 3 3 2 5 4"}) {
    const TriangleMesh m = read_mesh_from_memory(ply_header("ascii", "", strips) + grid_ascii() + list + "\n", "s.ply");
    EXPECT_EQ(canonical(m), want) << list;
  }
  // Binary, big-endian, an unsigned item type whose largest value restarts, beside a face element.
  std::string bin = ply_header("binary_big_endian", "",
                               "element face 1\nproperty list uchar int vertex_indices\nelement tristrips 1\n"
                               "property list uint uint vertex_indices\n");
  for (const Vec3& v : grid)
    for (int c = 0; c < 3; ++c) put(bin, float(v[c]), true);
  put(bin, uint8_t{3});
  for (int32_t i : {0, 2, 1}) put(bin, i, true);  // (0,0) (1,0) (0,1): counter-clockwise
  put(bin, uint32_t{9}, true);
  for (uint32_t i : {1u, 0u, 3u, 2u, 0xFFFFFFFFu, 3u, 2u, 5u, 4u}) put(bin, i, true);
  std::vector<test::PosTri> with_face = want;
  with_face.push_back({{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}});
  std::sort(with_face.begin(), with_face.end());
  EXPECT_EQ(canonical(read_mesh_from_memory(bin, "strips_be.ply")), with_face);
  // Ids out of range are refused; a strip of only degenerate triangles leaves none.
  EXPECT_TRUE(has(error_of<IoError>(ply_header("ascii", "", strips) + grid_ascii() + "3 0 1 6\n", "range.ply"),
                  "range.ply: tristrips 0 refers to vertex 6, the file has 6 vertices"));
  EXPECT_TRUE(has(error_of<InvalidInput>(ply_header("ascii", "", strips) + grid_ascii() + "4 0 0 1 1\n", "flat.ply"),
                  "flat.ply: holds no triangles"));
}

// A UTF-8 decoder and UTF-16 encoder of the test's own (RFC 3629, RFC 2781).
std::u32string decode_utf8(const std::string& s) {
  std::u32string out;
  for (size_t i = 0; i < s.size();) {
    const auto b = static_cast<unsigned char>(s[i]);
    const int n = b < 0x80 ? 1 : b < 0xE0 ? 2 : b < 0xF0 ? 3 : 4;
    char32_t c = n == 1 ? b : b & (0x3F >> (n - 1));
    for (int k = 1; k < n; ++k) c = (c << 6) | (static_cast<unsigned char>(s[i + k]) & 0x3F);
    out += c;
    i += n;
  }
  return out;
}
std::string encode_utf16(const std::string& utf8, bool big, bool mark) {
  std::u16string units;
  if (mark) units += char16_t(0xFEFF);
  for (char32_t c : decode_utf8(utf8)) {
    if (c < 0x10000) {
      units += char16_t(c);
    } else {
      units += char16_t(0xD800 + ((c - 0x10000) >> 10));
      units += char16_t(0xDC00 + ((c - 0x10000) & 0x3FF));
    }
  }
  std::string out;
  for (char16_t u : units) {
    out += char(big ? u >> 8 : u & 0xFF);
    out += char(big ? u & 0xFF : u >> 8);
  }
  return out;
}

TEST(MeshReaders, Utf16ObjReadsAsItsUtf8Twin) {
  // Comments and names outside ASCII (one beyond the BMP: a surrogate pair), CRLF line ends, a
  // concave polygon and a quad.
  const std::string utf8 =
      "# caf\xC3\xA9 \xE2\x98\x83 \xF0\x9D\x84\x9E\r\no n\xC3\xA4me\r\nv 0 0 0\r\nv 2 0 0\r\nv 2 2 0\r\nv 1 0.5 0\r\n"
      "v 0 2 0\r\nv 0 0 1\r\nv 1 0 1\r\nv 1 1 1\r\nv 0 1 1\r\nf 1 2 3 4 5\r\nf 6 7 8 9\r\n";
  const auto want = canonical(read_mesh_from_memory(utf8, "utf8.obj"));
  ASSERT_EQ(want.size(), 3u + 2u);
  for (bool big : {true, false})
    for (bool mark : {true, false}) {
      const std::string name = std::string(big ? "be" : "le") + (mark ? "_bom" : "") + ".obj";
      EXPECT_EQ(canonical(read_mesh_from_memory(encode_utf16(utf8, big, mark), name)), want) << name;
    }
  // A UTF-8 byte-order mark is skipped (else the first vertex would be an unknown statement).
  EXPECT_EQ(canonical(read_mesh_from_memory("\xEF\xBB\xBF" + utf8.substr(utf8.find("v 0 0 0")), "bom8.obj")), want);
  EXPECT_TRUE(has(error_of<IoError>(encode_utf16(utf8, true, true) + "x", "odd.obj"),
                  "odd.obj: UTF-16 text of an odd number of bytes"));
}

TEST(MeshReaders, ObjPointsAndLinesAreSkippedWithOneWarning) {
  // As assimp's testmixed.obj: a cube's six quads between point and line statements.
  const std::string cube =
      "v -1 -1 1\nv -1 -1 -1\nv -1 1 -1\nv -1 1 1\nv 1 -1 1\nv 1 -1 -1\nv 1 1 -1\nv 1 1 1\n"
      "l 4 3 2 1\nl 2 6 5 1\np 4 3 2 1\nf 3 7 6 2\np 3 7 6 2\nf 4 3 2 1\nf 2 6 5 1\nf 8 7 3 4\nf 5 8 4 1\nf 6 7 8 5\n";
  MeshReadReport report;
  const TriangleMesh m = read_mesh_from_memory(cube, "mixed.obj", {}, &report);
  EXPECT_EQ(m.faces.size(), 12u);
  EXPECT_EQ(m.vertices.size(), 8u);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_TRUE(has(report.warnings[0], "mixed.obj:9: skipped 2 line elements (l) and 2 point elements (p) (the first "
                                      "here)"))
      << report.warnings[0];
  EXPECT_TRUE(has(error_of<InvalidInput>("v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\np 1\n", "lines.obj"),
                  "lines.obj: holds no triangles: 2 line elements, 1 point element (3 vertices)"));
  EXPECT_TRUE(has(error_of<InvalidInput>("v 0 0 0\nvn 0 0 1\n", "cloud.obj"),
                  "cloud.obj: holds no triangles: no faces (1 vertex)"));
}

TEST(MeshReaders, FilesWithoutAnExtensionAreRecognisedByTheirContent) {
  const std::string off = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  const auto want = canonical(read_mesh_from_memory(off, "t.off"));
  std::string bin(80, ' ');
  put(bin, uint32_t{1});
  for (int c = 0; c < 3; ++c) put(bin, 0.0f);
  for (const Vec3& v : {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)})
    for (int c = 0; c < 3; ++c) put(bin, float(v[c]));
  put(bin, uint16_t{0});
  for (const std::string& bytes :
       {off, std::string("solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\n"
                         "endfacet\nendsolid t\n"),
        bin, std::string("# a triangle\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
        std::string("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                    "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")})
    EXPECT_EQ(canonical(read_mesh_from_memory(bytes, "formatDetection")), want) << bytes.substr(0, 12);
  test::TempDir dir;
  test::write_text(dir.file("noext"), off);
  EXPECT_EQ(canonical(read_mesh(dir.file("noext"))), want);
}

}  // namespace
}  // namespace hdm
