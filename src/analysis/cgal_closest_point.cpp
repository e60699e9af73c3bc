// SPDX-License-Identifier: MIT
// CGAL's AABB tree as a closest-point baseline; the only translation unit of hdm::reference.
#include <hdm/analysis/cgal_closest_point.h>
#include <hdm/core/error.h>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <chrono>
#include <vector>

namespace hdm {

namespace {
using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using Iterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, Iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
}  // namespace

struct CgalClosestPoint::Impl {
  std::vector<Triangle> triangles;
  Tree tree;
};

CgalClosestPoint::CgalClosestPoint(const TriangleMesh& mesh) : impl_(std::make_unique<Impl>()) {
  if (mesh.faces.empty()) throw InvalidInput("CGAL closest-point baseline: the mesh has no faces");
  const auto start = std::chrono::steady_clock::now();
  auto point = [&](int32_t v) { return Point(mesh.vertices[v].x(), mesh.vertices[v].y(), mesh.vertices[v].z()); };
  impl_->triangles.reserve(mesh.faces.size());
  for (const Tri& t : mesh.faces) impl_->triangles.emplace_back(point(t[0]), point(t[1]), point(t[2]));
  impl_->tree.insert(impl_->triangles.cbegin(), impl_->triangles.cend());
  impl_->tree.build();
  impl_->tree.accelerate_distance_queries();
  build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

CgalClosestPoint::~CgalClosestPoint() = default;

Vec3 CgalClosestPoint::closest_point(const Vec3& p) const {
  const Point c = impl_->tree.closest_point(Point(p.x(), p.y(), p.z()));
  return Vec3(c.x(), c.y(), c.z());
}

}  // namespace hdm
