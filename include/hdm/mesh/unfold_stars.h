// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Moves coarse vertices so that every vertex's star is seen whole from one direction.

#include <hdm/mesh/triangle_mesh.h>

#include <cstdint>

namespace hdm {

/// What unfold_stars() did.
struct UnfoldReport {
  int64_t folded_before = 0;  ///< vertices whose star no direction saw (before)
  int64_t folded_after = 0;   ///< vertices whose star no direction sees (after)
  int64_t moved = 0;          ///< vertices moved
};

/// @brief Unfolds the stars of a coarse mesh that no direction sees whole: around each vertex whose
/// incident face normals fit in no cap of visibility @p min_visibility (a crumple of the input that
/// the decimation kept), the disc of its k-ring (k = 1, 2, ... @p max_rings) is smoothed towards the
/// harmonic disc spanning the disc's boundary: every vertex strictly inside the disc steps a quarter
/// of the way to the mean of its neighbours per sweep (uniform Laplacian, the disc's boundary and
/// the mesh's boundary fixed). The first state, over k and then over 1, 2, ... 16, 32, ... 1,024
/// sweeps, that lowers the number of folded stars among the vertices of the disc's faces without
/// folding one that was not is kept; otherwise the disc is left as it was. Connectivity never
/// changes (genus, boundaries, components and orientation are kept).
///
/// Why: a slab needs a ray direction at each corner that sees every face around it, so a folded
/// star has no valid slab at any shell thickness (diplodocus.off: a crumple of the input's surface
/// gave invalid slabs at every slab count), and no edge collapse unfolds a crumple whose ring
/// itself is twisted. The harmonic disc is a graph over the plane of its boundary wherever that
/// boundary projects to a convex polygon (Tutte, "How to draw a graph", 1963: the uniform Laplacian
/// commutes with the projection, so the projected disc is Tutte's barycentric embedding), so each
/// of its stars is then seen from that plane's normal; the fewest sweeps that unfold keep the
/// moves small (a disc smoothed to convergence around a thin part flattens the part). The slabs'
/// displacement maps record the input wherever the coarse vertices lie.
/// @param[in,out] mesh  edge-manifold, consistently oriented triangles [model units]; positions
///                      of vertices near folded stars change.
/// @param min_visibility  a star is folded when the best direction's smallest dot product with its
///                        face normals is at most this, in [-1, 1).
/// @param max_rings  largest k of the discs tried, >= 1.
/// @return the counts.
/// @throws InvalidInput for a @p min_visibility outside [-1, 1), @p max_rings < 1, or invalid mesh
///         data (validate_mesh_data()).
/// @note O(#V) to find folded stars (exact max-min direction per barely seen star, O(k^3) for k
///       faces), plus O(r·s) per folded star for a disc of r vertices and s <= 1,024 sweeps;
///       deterministic.
UnfoldReport unfold_stars(TriangleMesh& mesh, double min_visibility = 0.0, int max_rings = 4);

}  // namespace hdm
