// SPDX-License-Identifier: MIT
// Debian's assimp-testmodels (installed by scripts/setup.sh): every OBJ, PLY, OFF and STL file of
// /usr/share/assimp/models, and the extension-less files of its OFF and STL folders, is read, or
// refused for a defect of its own (the table below names each); a few are checked against
// references computed here from the file's own text.
#include "io/mesh_test_util.h"

#include <hdm/core/error.h>
#include <hdm/io/read_mesh.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace hdm {
namespace {

namespace fs = std::filesystem;
using test::canonical;
using test::has;
using test::inside;
using test::shoelace;

const fs::path models = "/usr/share/assimp/models";

// The files refused, each with its defect and the part of the message that names it.
struct Refusal {
  const char* file;
  const char* message;
  const char* defect;
};
const Refusal refusals[] = {
    {"OBJ/number_formats.obj", "number_formats.obj:11: vertex 7: \"3.1+e2\" is not a number",
     "a malformed number (the exponent sign after the 'e' is written before it)"},
    {"OBJ/point_cloud.obj", "point_cloud.obj: holds no triangles: no faces (3 vertices)", "three vertices, no faces"},
    {"OBJ/testline.obj", "testline.obj: holds no triangles: 6 line elements (8 vertices)", "lines only"},
    {"OBJ/testpoints.obj", "testpoints.obj: holds no triangles: 6 point elements (8 vertices)", "points only"},
    {"PLY/points.ply", "points.ply: holds no triangles: no face element (4 vertices)", "a point cloud"},
    {"PLY/pond.0.ply", "pond.0.ply: holds no triangles: no face element (70,051 vertices)", "a point cloud"},
    {"PLY/issue623.ply", "issue623.ply: holds no triangles: no face element (24 vertices)",
     "no face element (its vertex element declares a list of vertex indices its data does not hold)"},
    {"OFF/invalid.off", "invalid.off:6: face 0 has no corners",
     "a face of no corners (its header claims 4 faces of 3 vertices; the lines after the vertices are 0, 220 and 4)"},
};

// The mesh files of the four formats: by extension (any case), and the extension-less files of
// the OFF and STL folders (formatDetection).
std::vector<fs::path> mesh_files() {
  std::vector<fs::path> files;
  for (const char* folder : {"OBJ", "PLY", "OFF", "STL"})
    for (const fs::directory_entry& e : fs::directory_iterator(models / folder)) {
      std::string ext = e.path().extension().string();
      for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      const bool no_ext = ext.empty() && (std::string(folder) == "OFF" || std::string(folder) == "STL");
      if (e.is_regular_file() && (no_ext || ext == ".obj" || ext == ".ply" || ext == ".off" || ext == ".stl"))
        files.push_back(e.path());
    }
  std::sort(files.begin(), files.end());
  return files;
}

TEST(AssimpTestModels, EveryFileIsReadOrRefusedForADefectOfItsOwn) {
  if (!fs::is_directory(models)) GTEST_SKIP() << models << " missing: install assimp-testmodels (scripts/setup.sh)";
  const std::vector<fs::path> files = mesh_files();
  EXPECT_GE(files.size(), 40u) << "the package's OBJ, PLY, OFF and STL files";
  std::map<std::string, const Refusal*> refused;
  for (const Refusal& r : refusals) refused[r.file] = &r;
  for (const fs::path& path : files) {
    const std::string file = path.parent_path().filename().string() + "/" + path.filename().string();
    const auto expected = refused.find(file);
    try {
      MeshReadReport report;
      const TriangleMesh m = read_mesh(path.string(), {}, &report);
      EXPECT_TRUE(expected == refused.end()) << file << " read, expected refused: " << expected->second->defect;
      ASSERT_FALSE(m.faces.empty()) << file;
      for (const Tri& f : m.faces)
        for (int32_t v : f) ASSERT_TRUE(v >= 0 && size_t(v) < m.vertices.size()) << file;
      for (const Vec3& v : m.vertices) ASSERT_TRUE(v.allFinite()) << file;
      std::cout << file << ": read: " << m.faces.size() << " triangles\n";
      for (const std::string& w : report.warnings) std::cout << "  warning: " << w << '\n';
    } catch (const std::exception& e) {
      std::cout << file << ": refused: " << e.what() << '\n';
      ASSERT_TRUE(expected != refused.end()) << file << " refused: " << e.what();
      EXPECT_TRUE(has(e.what(), expected->second->message)) << e.what();
      refused.erase(expected);
    }
  }
  for (const auto& [file, r] : refused) ADD_FAILURE() << file << " was expected to be refused (" << r->defect << ")";
}

// The one face of assimp's concave_polygon.obj (a LightWave ring of 64 vertices, written as one
// outline of 66 corners with a bridge run twice) against the file's own text: its triangles sum to
// the outline's shoelace area in the plane x = -1.146, each centroid lies inside it by the
// even-odd rule, and each is wound as the outline.
TEST(AssimpTestModels, ConcavePolygonTilesItsOutline) {
  for (const char* name : {"OBJ/concave_polygon.obj", "OBJ/space_in_material_name.obj"}) {
    const fs::path path = models / name;
    if (!fs::exists(path)) GTEST_SKIP() << path << " missing: install assimp-testmodels (scripts/setup.sh)";
    std::vector<Vec3> v, outline;  // (y, z, 0)
    std::ifstream in(path);
    for (std::string line; std::getline(in, line);) {
      std::istringstream s(line);
      std::string key;
      s >> key;
      if (key == "v") {
        double x, y, z;
        s >> x >> y >> z;
        v.emplace_back(y, z, 0);
      } else if (key == "f") {
        for (std::string corner; s >> corner;) outline.push_back(v.at(std::stoul(corner) - 1));
      }
    }
    ASSERT_EQ(outline.size(), 66u) << name;
    const TriangleMesh m = read_mesh(path.string());
    const double area = shoelace(outline);
    double sum = 0;
    for (const Tri& f : m.faces) {
      Vec3 p[3];
      for (int k = 0; k < 3; ++k) p[k] = Vec3(m.vertices[f[k]].y(), m.vertices[f[k]].z(), 0);
      const double z = (p[1] - p[0]).cross(p[2] - p[0]).z();
      EXPECT_GT(z * area, 0) << name << ": a triangle is flipped or flat";
      sum += 0.5 * z;
      EXPECT_TRUE(inside(outline, (p[0] + p[1] + p[2]) / 3)) << name << ": a triangle outside the outline";
    }
    EXPECT_NEAR(sum, area, 1e-5 * std::abs(area)) << name;
  }
}

// Files that are other files' twins: box_UTF16BE.obj is box.obj in UTF-16; testmixed.obj is a
// box's six quads between point and line statements, box_longline.obj one whose first face is
// written 234 times over; Wuson.ply (with a header line of Blender 2.4's own) is Wuson.off's
// triangles, wound the other way.
TEST(AssimpTestModels, TwinsReadAlike) {
  if (!fs::is_directory(models)) GTEST_SKIP() << models << " missing: install assimp-testmodels (scripts/setup.sh)";
  const TriangleMesh box = read_mesh((models / "OBJ/box.obj").string());
  EXPECT_EQ(box.faces.size(), 12u);
  EXPECT_EQ(canonical(read_mesh((models / "OBJ/box_UTF16BE.obj").string())), canonical(box));
  MeshReadReport report;
  EXPECT_EQ(read_mesh((models / "OBJ/testmixed.obj").string(), {}, &report).faces.size(), 12u);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_TRUE(has(report.warnings[0], "6 line elements (l) and 6 point elements (p)")) << report.warnings[0];
  report.warnings.clear();
  EXPECT_EQ(read_mesh((models / "OBJ/box_longline.obj").string(), {}, &report).faces.size(), 12u);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_TRUE(has(report.warnings[0], "is a cycle of 4 corners written")) << report.warnings[0];
  report.warnings.clear();
  TriangleMesh off = read_mesh((models / "OFF/Wuson.off").string());
  for (Tri& f : off.faces) std::swap(f[1], f[2]);
  EXPECT_EQ(canonical(read_mesh((models / "PLY/Wuson.ply").string(), {}, &report)), canonical(off));
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_TRUE(has(report.warnings[0], "Wuson.ply:3: skipped the PLY header line \"Created by")) << report.warnings[0];
}

}  // namespace
}  // namespace hdm
