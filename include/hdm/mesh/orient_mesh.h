// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Outward orientation of a consistently oriented mesh, part by part: what the bake and the
/// independent checks take as "outside".

#include <hdm/mesh/triangle_mesh.h>

#include <cstdint>

namespace hdm {

/// What orient_outward() found and changed.
struct OrientReport {
  int components = 0;         ///< connected components (through shared edges)
  int closed = 0;             ///< components without boundary edges
  int nearly_closed = 0;      ///< open components whose openings are small (see orient_outward())
  int sheets = 0;             ///< open components kept as given (surfaces, not solids)
  int flipped = 0;            ///< components whose faces were reversed
  int64_t flipped_faces = 0;  ///< faces reversed
};

/// @brief Orients every connected component of @p mesh outward, so that faces are counter-clockwise
/// seen from outside the material, as the slab model needs (paper §2; docs/design.md#slab-geometry).
///
/// - A closed component bounds a volume; it faces outward when its signed volume is positive at
///   an even nesting depth (not inside another closed component) and negative at an odd one (the
///   wall of a cavity), as CGAL's `orient_to_bound_a_volume` does. Nesting is counted by ray
///   parity of one of its vertices against every other closed component.
/// - An open component is *nearly closed* when its openings, each capped by a fan around the
///   centroid of its boundary loop, have less than a quarter of the component's area (a scan with a
///   cut neck, a head with an open base): it is oriented like a closed component by its capped
///   volume. Otherwise it is a *sheet* (a terrain, a mask, a thin panel): either side may be the
///   front, and the file's orientation is kept.
/// @param[in,out] mesh  consistently oriented triangles (repair_mesh() first for a soup); vertices
///                      are not moved.
/// @return what was found and changed.
/// @note O(#F log #F + C·#F) for C closed or nearly closed components; single-threaded.
OrientReport orient_outward(TriangleMesh& mesh);

}  // namespace hdm
