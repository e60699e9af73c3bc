// SPDX-License-Identifier: MIT
// What other readers read, against meshes written here: PLY header lines of other programs
// (skipped with a warning), PLY triangle strips (against the triangles worked out by hand) and
// OBJ points and lines (skipped with one warning).
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

}  // namespace
}  // namespace hdm
