// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// The same surface with well-shaped triangles. CAD exports tessellate a flat face with holes as
/// fans of needles between its boundary vertices; no vertex direction keeps a slab over a needle
/// valid once its shell is thicker than the needle is wide, so where the bake's slabs stay invalid
/// at the input's own resolution, bake_input() decimates an isotropic remesh of the input instead
/// (BakeOptions::source), still casting the rays on the input.

#include <hdm/mesh/triangle_mesh.h>

namespace hdm {

/// @brief Isotropic remeshing that keeps sharp features: every edge near @p edge_length, vertices
/// on the input surface, the sharp edges (dihedral turn over 60°) and the boundary kept as
/// polylines (split, never collapsed or moved off them).
///
/// CGAL's `Polygon_mesh_processing::isotropic_remeshing` (three iterations of split, collapse,
/// flip and tangential relaxation with projection back onto the input; Botsch & Kobbelt, "A
/// remeshing approach to multiresolution modeling", SGP 2004), after `detect_sharp_edges` and
/// `split_long_edges` on the protected edges.
/// @param mesh         edge-manifold, consistently oriented triangles [model units] (validate_for_bake()).
/// @param edge_length  target edge length [model units], > 0.
/// @return the remeshed surface, closed where @p mesh is closed, oriented as it is.
/// @throws InvalidInput for a mesh validate_for_bake() refuses or a non-positive @p edge_length.
/// @note Cost: about 1 s per 10,000 output triangles on one core; the output has about
///       4 · area / (√3 · edge_length²) triangles, plus those the protected edges need.
TriangleMesh remesh_isotropic(const TriangleMesh& mesh, double edge_length);

}  // namespace hdm
