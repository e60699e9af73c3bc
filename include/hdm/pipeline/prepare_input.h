// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// A mesh as read, made ready to bake: one size, repaired, oriented outward, its crossings and
/// folds handled. The bake (bake_input()) and the check against the input (`hdm check`) both start
/// here, so that both see the same surface.

#include <hdm/mesh/orient_mesh.h>
#include <hdm/mesh/remove_folds.h>
#include <hdm/mesh/repair_mesh.h>
#include <hdm/mesh/self_intersections.h>
#include <hdm/mesh/stitch_seams.h>
#include <hdm/mesh/triangle_mesh.h>

#include <cstdint>
#include <string>
#include <vector>

namespace hdm {

/// Options of prepare_input().
struct PrepareOptions {
  bool repair = true;           ///< false: refuse a dirty mesh (validate_for_bake()) instead of repairing it
  int max_hole_edges = 64;      ///< RepairOptions::max_hole_edges
  double max_hole_size = 0.05;  ///< RepairOptions::max_hole_size [fraction of the diagonal]
  /// true: faces that cross are replaced by resolve_self_intersections() of the mesh (what the bake
  /// follows); false: kept as they are (the reference a check measures against).
  bool resolve = true;
};

/// What prepare_input() found and did, in order.
struct PrepareReport {
  int scale_exponent = 0;           ///< scale_exponent() of the mesh as given; scale_model(m, -k) gives its units back
  RepairReport repair;              ///< what repair_mesh() did (nothing when the mesh needed no repair)
  OrientReport orient;              ///< the parts of the mesh as repaired, and which were reversed
  int64_t self_intersections = 0;   ///< face pairs that cross, counted after orientation
  SeamReport seams;                 ///< open parts that cross: what stitch_seams() joined
  int64_t filled_faces = 0;         ///< faces added to close a nearly closed mesh that crosses itself
  FoldReport folds;                 ///< open input: what remove_folds() did
  SelfIntersectionReport resolved;  ///< with PrepareOptions::resolve: what resolve_self_intersections() did
};

/// A mesh made ready to bake, with the report of what was done to it.
struct PreparedInput {
  TriangleMesh mesh;     ///< scaled by 2^report.scale_exponent (diagonal in [1, 2)) and prepared
  PrepareReport report;  ///< see PrepareReport
  /// With PrepareOptions::resolve, where faces cross: the points of the material's surface on the
  /// faces before step 7 (surface_points() with interior_faces()), which the bake's fidelity
  /// measures from the input to the model. `hdm check` measures against those same faces, so the
  /// bake and the check measure the same points. Empty otherwise.
  std::vector<Vec3> surface_points;
};

/// @brief Makes a mesh as read ready to bake, in the one order every front end uses.
///
/// 1. validate_mesh_data(); scale by a power of two to a diagonal in [1, 2) (scale_mesh(), exact:
///    every later step works at one size, and the model goes back to the input's units exactly).
/// 2. Repair when needs_repair() (repair_mesh()); with PrepareOptions::repair false,
///    validate_for_bake() instead.
/// 3. orient_outward(), then count the face pairs that cross.
/// 4. Open parts that cross where they should meet (CAD patch soups, game assets in parts) are
///    joined at their seams (stitch_seams()) and oriented again as one surface.
/// 5. A nearly closed mesh that still crosses itself (a bust with an open base) becomes the solid
///    it nearly bounds (fill_nearly_closed()).
/// 6. An open sheet's folds (a scan's flaps and crumples, where no slab is valid and no
///    displacement single-valued) are removed (remove_folds()), after the seams are joined so a
///    seam is not taken for a fold.
/// 7. With PrepareOptions::resolve, faces that still cross are replaced by
///    resolve_self_intersections() of the mesh, unless the seams closed it (CGAL 5.5's
///    refinement of such a closed union can fail; what crosses then stays as the input has it).
///    The points of the material's surface are taken before (PreparedInput::surface_points).
///
/// @param mesh     triangles as read [any units].
/// @param name     file or argument name for error messages.
/// @param options  see PrepareOptions.
/// @return the prepared mesh and its report.
/// @throws InvalidInput naming @p name for invalid mesh data, a diagonal outside
///         [kMinDiagonal, kMaxDiagonal], a mesh repair_mesh() cannot repair, or (repair off) a
///         mesh validate_for_bake() refuses.
/// @note Cost: O(#F log #F) for the repair, orientation and crossing count (CGAL box
///       intersection); the seam, fold and resolution steps run only where the mesh crosses
///       itself or is open.
PreparedInput prepare_input(TriangleMesh mesh, const std::string& name, const PrepareOptions& options = {});

}  // namespace hdm
