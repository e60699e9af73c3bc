// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// A second exact closest-point baseline on the input mesh: CGAL's AABB tree (`hdm bench`).

#include <hdm/mesh/triangle_mesh.h>

#include <memory>

namespace hdm {

/// CGAL's AABB tree over the triangles of a mesh, with its distance-query acceleration (a kd-tree
/// of sample points that gives the first hint): what a user without hdm, and with CGAL, would call
/// for the closest point (CGAL manual, "3D Fast Intersection and Distance Computation (AABB
/// Tree)"). Used as a baseline next to ExactMeshQuery (Embree); nothing in hdm's core depends on
/// it. CGAL is confined to this class's one translation unit (target hdm::reference).
///
/// Threading: closest_point() is const and may be called from any number of threads at once
/// (CGAL's AABB tree queries are read-only once built).
class CgalClosestPoint {
 public:
  /// @brief Copies the triangles of @p mesh [model units] and builds the tree and its
  /// distance-query acceleration.
  /// @throws InvalidInput for a mesh with no faces.
  /// @note O(#F log #F) time; about 200 bytes per triangle (CGAL stores the triangles and boxes).
  explicit CgalClosestPoint(const TriangleMesh& mesh);
  ~CgalClosestPoint();
  CgalClosestPoint(const CgalClosestPoint&) = delete;
  CgalClosestPoint& operator=(const CgalClosestPoint&) = delete;

  /// @brief The closest point of the mesh to @p p [model units, model frame].
  /// @pre @p p finite.
  /// @note Double precision (CGAL's Simple_cartesian<double> kernel); cost O(log #F) typical.
  Vec3 closest_point(const Vec3& p) const;

  /// Seconds the constructor took (tree and acceleration).
  double build_seconds() const noexcept { return build_seconds_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  double build_seconds_ = 0;
};

}  // namespace hdm
