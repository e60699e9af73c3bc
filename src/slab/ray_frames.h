// SPDX-License-Identifier: MIT
#pragma once
// Internal to the bake: the coarse mesh it works on and the ray direction at each coarse vertex
// (docs/design.md#ray-directions).

#include <hdm/core/types.h>

#include <cstdint>
#include <vector>

namespace hdm::slab::detail {

// The coarse triangle mesh whose faces become slabs [model units].
struct CoarseMesh {
  std::vector<Vec3> vertices;
  std::vector<Tri> faces;
};

// Per coarse vertex: its unit ray direction, the mean length of its incident edges, and its
// incident faces (CSR: faces[offsets[v] .. offsets[v + 1]]); per face its unit normal.
struct VertexFrame {
  std::vector<Vec3> direction;
  std::vector<double> edge;
  std::vector<int32_t> offsets, faces;
  std::vector<Vec3> face_normal;
};

// The smallest dot product of @p d with @p normals (2 for none).
double min_dot(const Vec3& d, const std::vector<Vec3>& normals);

// The unit direction that maximises the smallest dot product with the unit @p normals (the centre
// of the smallest spherical cap holding them), from @p start (kept when it already scores above
// 0.5, so the field stays smooth). O(k^3) for k normals up to 24 (improve_max_min()).
Vec3 max_min_direction(const Vec3& start, const std::vector<Vec3>& normals);

// Frames of every vertex of @p c: each direction has a positive dot product with every incident
// face normal where one exists, which guarantees a positive Jacobian for a thin enough shell; then
// @p smoothing Laplacian sweeps of the directions, each step kept only while the vertex still sees
// its faces. O(#V) per sweep.
VertexFrame vertex_frames(const CoarseMesh& c, int smoothing);

}  // namespace hdm::slab::detail
