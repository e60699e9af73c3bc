// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// A rigid tool as a point shell: points on the tool's surface with inward normals, in the tool's
/// own frame, queried against the slab field by the 6-DOF god-object (rigid_tool.h). After the
/// voxel-sampling point shell of McNeely, Puterbaugh & Troy 1999.

#include <hdm/mesh/triangle_mesh.h>

#include <vector>

namespace hdm {

/// Most points a ToolShell may hold for rigid_tool_step() (its per-point state is fixed-size).
inline constexpr int kMaxToolPoints = 2048;

/// Points on a rigid tool's surface, tool frame [model units].
///
/// `points` and `normals` are both #P by 3, #P in [1, kMaxToolPoints] for rigid_tool_step().
/// The tool frame's origin is the tool's tip point: the point the device reports (rigid_tool.h).
struct ToolShell {
  std::vector<Vec3> points;   ///< #P surface points [model units, tool frame]
  std::vector<Vec3> normals;  ///< #P unit normals pointing into the tool [tool frame]
};

/// @brief Samples @p count points area-uniformly on @p mesh (the tool's surface, given in the tool
/// frame), each with the inward normal of its triangle.
///
/// Deterministic: point k lies in the triangle where the cumulative area reaches (k + ½)/count of
/// the total (stratified inverse-CDF sampling), at the k-th point of the R2 low-discrepancy
/// sequence folded into that triangle, so equal inputs give equal shells on every platform.
///
/// @param mesh   #V vertices, #F triangles counter-clockwise seen from outside [model units, tool frame].
/// @param count  number of points, in [1, kMaxToolPoints].
/// @return the shell: #P = @p count.
/// @pre @p mesh is oriented outward (the normals are negated face normals).
/// @throws InvalidInput for a count outside [1, kMaxToolPoints], a mesh without faces, a vertex id
///         out of range, non-finite vertices or a zero total area (naming the reason).
/// @note O(#F + count·log #F), allocates the shell. Not for the servo thread.
/// @see McNeely, Puterbaugh & Troy 1999 (point shell with inward normals); Roberts 2018 (the R2
///      sequence).
ToolShell sample_tool_shell(const TriangleMesh& mesh, int count = 1000);

/// @brief The point shell of a dental burr, built analytically: a spherical head of radius
/// @p radius centred at the origin (the tip point) on a cylindrical shaft of radius 0.4·radius
/// along +z, from where it leaves the head to 8·radius above that, closed by a flat end.
///
/// Points are spread in proportion to each part's area (head without the cap the shaft covers,
/// shaft side, end disc): Fibonacci spirals on the head (uniform in z) and the side, a sunflower
/// (Vogel) spiral on the end; deterministic.
///
/// @param radius  head radius r [model units], > 0.
/// @param count   number of points, in [16, kMaxToolPoints].
/// @return the shell [model units, tool frame], inward unit normals.
/// @throws InvalidInput for a radius that is not positive and finite or a count out of range.
/// @note O(count), allocates the shell. Not for the servo thread.
/// @see Vogel 1979 (sunflower spiral); González 2010 (Fibonacci sphere).
ToolShell burr_shell(double radius, int count = 1000);

}  // namespace hdm
