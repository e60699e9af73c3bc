// SPDX-License-Identifier: MIT
#pragma once
// Helpers of the reader tests, each computed here from first principles: meshes compared up to
// vertex numbering, the error a read throws, and a polygon's shoelace area and even-odd inside
// test.

#include <hdm/core/error.h>
#include <hdm/io/read_mesh.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <exception>
#include <sstream>
#include <string>
#include <vector>

namespace hdm::test {

/// Triangles as position triples rotated to start at the smallest corner (keeps the winding),
/// sorted: equal for two meshes with the same triangles, whatever the vertex numbering.
using PosTri = std::array<std::array<double, 3>, 3>;
inline std::vector<PosTri> canonical(const TriangleMesh& m, bool as_float = false) {
  std::vector<PosTri> out;
  for (const Tri& f : m.faces) {
    PosTri t;
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) t[k][c] = as_float ? double(float(m.vertices[f[k]][c])) : m.vertices[f[k]][c];
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    out.push_back(t);
  }
  std::sort(out.begin(), out.end());
  return out;
}

/// The error read_mesh_from_memory throws for @p bytes, checked to be an E naming @p name.
template <class E>
std::string error_of(const std::string& bytes, const std::string& name, const MeshReadOptions& o = {}) {
  try {
    read_mesh_from_memory(bytes, name, o);
  } catch (const E& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(name, 0), 0u) << "the message must start with the file name: " << msg;
    return msg;
  } catch (const std::exception& e) {
    ADD_FAILURE() << name << ": wrong exception type: " << e.what();
    return e.what();
  }
  ADD_FAILURE() << name << ": no exception";
  return "";
}

inline bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

/// Twice the signed area of the closed polygon @p p in the z = 0 plane, over 2 (shoelace formula).
inline double shoelace(const std::vector<Vec3>& p) {
  double a = 0;
  for (size_t k = 0; k < p.size(); ++k)
    a += p[k].x() * p[(k + 1) % p.size()].y() - p[(k + 1) % p.size()].x() * p[k].y();
  return 0.5 * a;
}

/// Ray-crossing (even-odd) point-in-polygon test in the z = 0 plane.
inline bool inside(const std::vector<Vec3>& poly, const Vec3& q) {
  bool in = false;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++)
    if ((poly[i].y() > q.y()) != (poly[j].y() > q.y()) &&
        q.x() < (poly[j].x() - poly[i].x()) * (q.y() - poly[i].y()) / (poly[j].y() - poly[i].y()) + poly[i].x())
      in = !in;
  return in;
}

/// An OBJ file of the vertices @p poly and one face through them in order.
inline std::string polygon_obj(const std::vector<Vec3>& poly) {
  std::ostringstream s;
  s.precision(17);
  for (const Vec3& v : poly) s << "v " << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
  s << 'f';
  for (size_t k = 1; k <= poly.size(); ++k) s << ' ' << k;
  s << '\n';
  return s.str();
}

}  // namespace hdm::test
