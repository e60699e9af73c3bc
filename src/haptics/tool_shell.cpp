// SPDX-License-Identifier: MIT
#include <hdm/haptics/tool_shell.h>

#include <hdm/core/error.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace hdm {
namespace {

// The R2 sequence's generators (Roberts 2018): 1/φ₂ and 1/φ₂², φ₂ the plastic number.
constexpr double kR2a = 0.7548776662466927, kR2b = 0.5698402909980532;

void check_count(int count, int least, const char* what) {
  if (count < least || count > kMaxToolPoints)
    throw InvalidInput(std::string(what) + ": count " + std::to_string(count) + " is outside [" +
                       std::to_string(least) + ", " + std::to_string(kMaxToolPoints) + "]");
}

void add(ToolShell& s, const Vec3& p, const Vec3& inward) {
  s.points.push_back(p);
  s.normals.push_back(inward);
}

}  // namespace

ToolShell sample_tool_shell(const TriangleMesh& mesh, int count) {
  check_count(count, 1, "sample_tool_shell");
  if (mesh.faces.empty()) throw InvalidInput("sample_tool_shell: the mesh has no faces");
  const int32_t nv = static_cast<int32_t>(mesh.vertices.size());
  std::vector<double> cumulative(mesh.faces.size());
  double total = 0;
  for (size_t f = 0; f < mesh.faces.size(); ++f) {
    for (int32_t v : mesh.faces[f])
      if (v < 0 || v >= nv)
        throw InvalidInput("sample_tool_shell: face " + std::to_string(f) + " has a vertex id out of range");
    const Vec3 &a = mesh.vertices[mesh.faces[f][0]], &b = mesh.vertices[mesh.faces[f][1]],
               &c = mesh.vertices[mesh.faces[f][2]];
    if (!a.allFinite() || !b.allFinite() || !c.allFinite())
      throw InvalidInput("sample_tool_shell: face " + std::to_string(f) + " has a non-finite vertex");
    total += 0.5 * (b - a).cross(c - a).norm();
    cumulative[f] = total;
  }
  if (!(total > 0)) throw InvalidInput("sample_tool_shell: the mesh has zero area");
  ToolShell s;
  s.points.reserve(count);
  s.normals.reserve(count);
  for (int k = 0; k < count; ++k) {
    const double at = (k + 0.5) / count * total;
    const size_t f = std::min(size_t(std::lower_bound(cumulative.begin(), cumulative.end(), at) - cumulative.begin()),
                              cumulative.size() - 1);
    const Vec3 &a = mesh.vertices[mesh.faces[f][0]], &b = mesh.vertices[mesh.faces[f][1]],
               &c = mesh.vertices[mesh.faces[f][2]];
    double u = std::fmod(0.5 + kR2a * (k + 1), 1.0), v = std::fmod(0.5 + kR2b * (k + 1), 1.0);
    if (u + v > 1) u = 1 - u, v = 1 - v;  // fold the square onto the triangle: still uniform
    const Vec3 n = (b - a).cross(c - a);
    add(s, a + u * (b - a) + v * (c - a), n.norm() > 0 ? Vec3(-n.normalized()) : Vec3(-Vec3::UnitZ()));
  }
  return s;
}

ToolShell burr_shell(double radius, int count) {
  if (!(radius > 0) || !std::isfinite(radius))
    throw InvalidInput("burr_shell: radius " + std::to_string(radius) + " is not positive and finite");
  check_count(count, 16, "burr_shell");
  const double r = radius, rs = 0.4 * r;                          // head and shaft radii
  const double z0 = std::sqrt(r * r - rs * rs), z1 = z0 + 8 * r;  // the shaft leaves the head at z0, ends at z1
  const double head_area = 2 * std::numbers::pi * r * (r + z0);   // the sphere below z = z0
  const double side_area = 2 * std::numbers::pi * rs * (z1 - z0), end_area = std::numbers::pi * rs * rs;
  const double total = head_area + side_area + end_area;
  const int head = std::max(1, static_cast<int>(std::lround(count * head_area / total)));
  const int end = std::max(1, static_cast<int>(std::lround(count * end_area / total)));
  const int side = count - head - end;
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  ToolShell s;
  s.points.reserve(count);
  s.normals.reserve(count);
  // The head: uniform in z is uniform in area on a sphere (Archimedes), turned by the golden angle.
  for (int k = 0; k < head; ++k) {
    const double z = -r + (r + z0) * (k + 0.5) / head;
    const double rho = std::sqrt(std::max(0.0, r * r - z * z));
    const Vec3 p(rho * std::cos(golden * k), rho * std::sin(golden * k), z);
    add(s, p, -p / r);
  }
  for (int k = 0; k < side; ++k) {
    const double z = z0 + (z1 - z0) * (k + 0.5) / side, a = golden * k;
    add(s, Vec3(rs * std::cos(a), rs * std::sin(a), z), Vec3(-std::cos(a), -std::sin(a), 0));
  }
  for (int k = 0; k < end; ++k) {
    const double rho = rs * std::sqrt((k + 0.5) / end), a = golden * k;
    add(s, Vec3(rho * std::cos(a), rho * std::sin(a), z1), -Vec3::UnitZ());
  }
  return s;
}

}  // namespace hdm
