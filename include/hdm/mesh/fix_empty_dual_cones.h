// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Moves coarse vertices so that every vertex's dual cone is not empty: some direction has a
/// positive dot product with every face normal around it. Terms: the *normal cone* of a vertex is
/// the cone of its incident face normals; its *dual cone* holds the directions d with d·n > 0 for
/// each of them, and is empty when the normals fit in no open hemisphere; the *cone margin* is
/// max over unit d of min over the normals n of d·n (positive exactly when the dual cone is not
/// empty).

#include <hdm/mesh/triangle_mesh.h>

#include <cstdint>

namespace hdm {

/// What fix_empty_dual_cones() did.
struct DualConeReport {
  int64_t empty_cones_before = 0;  ///< vertices whose dual cone was empty (before)
  int64_t empty_cones_after = 0;   ///< vertices whose dual cone is empty (after)
  int64_t moved = 0;               ///< vertices moved
};

/// @brief Gives every vertex of a coarse mesh a non-empty dual cone: around each vertex whose cone
/// margin is at most @p min_cone_margin (a crumple of the input that
/// the decimation kept), the disc of its k-ring (k = 1, 2, ... @p max_rings) is smoothed towards the
/// harmonic disc spanning the disc's boundary: every vertex strictly inside the disc steps a quarter
/// of the way to the mean of its neighbours per sweep (uniform Laplacian, the disc's boundary and
/// the mesh's boundary fixed). The first state, over k and then over 1, 2, ... 16, 32, ... 1,024
/// sweeps, that lowers the number of empty-cone vertices among the vertices of the disc's faces without
/// emptying the cone of one that was not is kept; otherwise the disc is left as it was. Connectivity never
/// changes (genus, boundaries, components and orientation are kept).
///
/// Why: a slab needs a ray direction at each corner that sees every face around it, so an
/// empty-cone vertex has no valid slab at any shell thickness (diplodocus.off: a crumple of the input's surface
/// gave invalid slabs at every slab count), and no edge collapse opens the cones of a crumple whose ring
/// itself is twisted. The harmonic disc is a graph over the plane of its boundary wherever that
/// boundary projects to a convex polygon (Tutte, "How to draw a graph", 1963: the uniform Laplacian
/// commutes with the projection, so the projected disc is Tutte's barycentric embedding), so each
/// of its stars is then seen from that plane's normal; the fewest sweeps that open the cones keep the
/// moves small (a disc smoothed to convergence around a thin part flattens the part). The slabs'
/// displacement maps record the input wherever the coarse vertices lie.
/// @param[in,out] mesh  edge-manifold, consistently oriented triangles [model units]; positions
///                      of vertices near empty-cone vertices change.
/// @param min_cone_margin  a vertex's dual cone counts as empty when its cone margin (the best
///                        direction's smallest dot product with its face normals) is at most this, in [-1, 1);
///                        for a margin >= 0, a cone margin up to 1e-6 counts as empty too (the normals'
///                        hull holds the origin to within rounding).
/// @param max_rings  largest k of the discs tried, >= 1.
/// @return the counts.
/// @throws InvalidInput for a @p min_cone_margin outside [-1, 1), @p max_rings < 1, or invalid mesh
///         data (validate_mesh_data()).
/// @note O(#V) to find empty-cone vertices (per barely seen star of k faces, the nearest point of
///       the normals' hull to the origin, Wolfe 1976: a few O(k) cycles; the max-min candidates,
///       O(k^3), only for a seen star of more than 24 faces or a negative margin), plus O(r·s) per
///       empty-cone vertex for a disc of r vertices and s <= 1,024 sweeps (a state is judged star by
///       star, the vertex first, up to its first failing star); deterministic.
DualConeReport fix_empty_dual_cones(TriangleMesh& mesh, double min_cone_margin = 0.0, int max_rings = 4);

}  // namespace hdm
