// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Folds of an open sheet (a reconstructed scan's flaps and crumples) removed before the bake.

#include <hdm/mesh/triangle_mesh.h>

#include <cstdint>

namespace hdm {

/// What remove_folds() did.
struct FoldReport {
  int64_t flap_faces = 0;          ///< faces of rim flaps removed (step 1)
  int64_t empty_cones_before = 0;  ///< vertices whose dual cone is empty (cone margin <= 0.02), after step 1
  int64_t moved = 0;               ///< vertices moved to give them a non-empty dual cone (step 2)
  double max_move = 0;             ///< largest such move [model units]
  int64_t rim_faces = 0;           ///< faces removed at empty-cone vertices left (step 3)
  int64_t empty_cones_after = 0;   ///< the same at the end
  double max_deviation = 0;        ///< how far the surface changed: the largest distance from a vertex or
                                   ///< face centroid of the mesh before or after to the other [model units]
};

/// @brief Removes the folds of an open sheet that no slab can hold: where a surface turns back
/// over itself within a ring of faces, no direction sees every face of a star, so there is no valid
/// slab shell and no single-valued displacement map (b9_mesh.off, a surface reconstructed from a
/// scanned part: 39 rim flaps, 36 empty-cone vertices, and 0.7-1.5 % of its diagonal lost by the model).
/// A vertex's dual cone is *empty* (fix_empty_dual_cones.h) when its cone margin, the best direction's
/// smallest dot product with its face normals, is at
/// most 0.02 (as in the decimation), or at most 0.1 (84°) for a vertex on the mesh's boundary.
/// Three steps:
/// 1. **Rim flaps**: the faces are joined across edges where they turn by less than 120°; a group
///    of at most 6 faces that holds a boundary edge of the mesh, spans at most 5 % of the mesh's
///    diagonal (as the holes repair_mesh() fills) and is not a whole part (so every edge it shares
///    with the rest turns back by more than 120°: a strip folded over the faces it hangs from) is
///    removed.
/// 2. **Crumples**: fix_empty_dual_cones() with cone margin 0.02 and up to 4 rings (interior vertices move,
///    the boundary stays).
/// 3. **Empty-cone vertices left**: in rounds (at most 8), each empty-cone vertex loses the face turned farthest
///    from its best direction that can go. A star seen at a dot in (0.02, 0.1] (a rim that turns
///    back steeply but is seen) loses it only if that leaves fewer empty-cone vertices among the face's
///    corners and folds none that was not: a cut in a pleat would only move the fold.
/// A face is removed only when none of its corners ends up in more fans of faces than before (no
/// vertex becomes a pinch); vertices no face uses are dropped. Faces and vertices keep their order,
/// faces their orientation. Vertices move only in step 2, and are reported.
/// @param[in,out] mesh  edge-manifold, consistently oriented triangles [model units].
/// @return the counts.
/// @throws InvalidInput for invalid mesh data (validate_mesh_data()).
/// @note O(#F) per step and round, plus fix_empty_dual_cones()' cost, plus O(#F log #F) exact closest
///       points (Embree) for FoldReport::max_deviation when anything changed; deterministic.
FoldReport remove_folds(TriangleMesh& mesh);

}  // namespace hdm
