// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Decimation that cannot break the mesh: the coarse mesh the bake turns into slabs.

#include <hdm/mesh/triangle_mesh.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace hdm {

/// Options of decimate_mesh().
struct DecimateOptions {
  int64_t target_faces = 0;  ///< stop once the mesh has at most this many faces (the collapses
                             ///< the guarantees allow may end above it)
  /// Edges whose dihedral angle (between the two face normals) exceeds this are creases; boundary
  /// edges always are features. Penalty planes keep the coarse vertices on features, and
  /// collapses run along them, so slab edges end up on the creases of CAD-like parts [degrees].
  double feature_angle_deg = 40.0;
  double feature_weight = 20.0;  ///< weight of a feature's penalty planes against the face planes
  /// A collapse is refused when it turns a face normal of its star by more than this [degrees]
  /// (no fold-overs, and stars stay visible from one ray direction, which slabs need).
  double max_normal_turn_deg = 75.0;
  /// A collapse is refused when a face it makes has a smallest angle below this [degrees], unless
  /// the faces it replaces were already that thin (slivers make slabs of little volume).
  double min_angle_deg = 2.0;
  /// A collapse is refused when it leaves a vertex (the new one, or one of its link) whose faces
  /// no direction sees with a dot product of at least this, unless that vertex was already worse
  /// seen (a slab needs a ray direction at each corner that sees every face around it; the
  /// larger the margin, the thicker a valid shell can grow).
  double min_cone_margin = 0.2;
  /// true: each collapse keeps the end of least quadric error (a half-edge collapse), so coarse
  /// vertices are input vertices and lie on the surface (but for an input's empty-cone vertex, which
  /// a reopening collapse may resolve at the edge's midpoint); false: the quadric's minimiser, which
  /// follows the input more closely between vertices but puts vertices off the surface.
  bool on_input = true;
  /// Optional #V per input vertex: the longest edge a collapse may make at a vertex merged from
  /// it [model units]: an edge a collapse makes is at most the smallest value of the input
  /// vertices merged into its two ends (+inf or an empty vector: no limit; input edges stay).
  /// Local refinement: where a coarse mesh made faulty slabs, the next decimation keeps its faces
  /// smaller there and nowhere else.
  std::vector<double> max_edge;
  /// Stop once the cheapest remaining collapse costs more quadric error than this (in the
  /// quadric's units: area-weighted squared distance [model units⁴]); +inf: target_faces alone.
  /// With DecimateReport::last_cost of an earlier run and max_edge, a region is refined while
  /// the rest of the mesh decimates as far as before.
  double max_cost = INFINITY;
};

/// What decimate_mesh() did.
struct DecimateReport {
  int64_t faces = 0;          ///< faces of the result
  int64_t vertices = 0;       ///< vertices of the result
  int64_t feature_edges = 0;  ///< input edges marked as features (creases and boundary; for an
                              ///< input decimated in parts first, those of the joined parts)
  int64_t collapses = 0;      ///< edge collapses made
  double last_cost = 0;       ///< largest quadric error of a collapse the queue made (DecimateOptions::max_cost)
};

/// @brief Decimates @p mesh by edge collapses ordered by Garland–Heckbert quadric error, each one
/// checked so that the result keeps the input's topology and can be turned into valid slabs.
///
/// Quadrics: area-weighted face planes, plus, for each feature edge (boundary, or a crease sharper
/// than DecimateOptions::feature_angle_deg), the planes through the edge perpendicular to its
/// faces (Garland & Heckbert, "Surface Simplification Using Quadric Error Metrics", SIGGRAPH 1997,
/// §6, extended from boundaries to creases). By default (DecimateOptions::on_input) each collapse
/// keeps the end of least quadric error, so coarse vertices are input vertices; otherwise the new
/// vertex goes to the quadric's minimiser, regularised towards the edge midpoint (Lindstrom 2000).
/// A collapse is made only when:
/// - the link condition holds (Dey, Edelsbrunner, Guha, Nekhayev, "Topology preserving edge
///   contraction", 1999): the common neighbours of the two ends are exactly the apexes of the
///   edge's faces, an interior edge does not join two boundary vertices, and no two faces would
///   become duplicates; so the result is 2-manifold with the input's genus, boundary loops,
///   components and orientation (faces keep their vertex order);
/// - no face it moves turns its normal by more than DecimateOptions::max_normal_turn_deg (no
///   fold-over) or becomes a new sliver (DecimateOptions::min_angle_deg), unless it moves the
///   face's vertex by at most 1e-5 of the mesh's bounding-box diagonal;
/// - every vertex whose star changes keeps a direction that sees all its faces
///   (DecimateOptions::min_cone_margin): thin parts, tubes and tips stop the decimation early
///   instead of giving vertices no valid slab direction, so the face count follows the shape.
///
/// Edges no longer than 1e-5 of the diagonal (two vertices of a CAD export a few micrometres
/// apart, where an arc meets a line) are collapsed first, with the same checks, whatever their
/// quadric cost: in cost order a plate's flat collapses, which cost nothing, reach the target
/// before them, and the coarse mesh kept each with the slivers beside it, invalid slabs at any
/// slab count.
///
/// Stars of the input that no direction sees (an empty dual cone: a crumple of a scanned surface) are collapsed
/// first; those left at the end are merged into a neighbour, or the vertex removed and its ring
/// filled, beyond the target; a crumple whose cones neither opens (its ring twists over itself) is
/// merged whole into its empty-cone vertex when that leaves fewer empty-cone vertices around it and folds no
/// other (its vertices within 1/4, 1/2 or 1 of the vertex's mean edge length, by collapses under
/// the link condition alone, placed at the best of their places and their centroid; undone
/// otherwise).
///
/// A large input (at least 2²⁰ faces and 64 times target_faces) is first
/// decimated in spatial parts of about 2¹⁷ faces along a Morton curve, in parallel, each to its share
/// of 16 times target_faces, with the vertices where parts meet and every edge to them left as
/// they are; the joined parts, the same surface and topology, are then decimated as above, each
/// joined vertex capped by the least max_edge of the input vertices merged into it. On
/// armadillo subdivided to 4.2 M triangles, to 8,000 faces: 11 s instead of 35 s, the faces' largest
/// distance to the input 0.305 % of the diagonal instead of 0.325 % (docs/performance.md).
///
/// @param mesh  input [model units]: edge-manifold, consistently oriented triangles (as after
///              repair_mesh()); closed or open; any genus and number of components. A vertex shared
///              by two fans of faces (a pinch) is split into one vertex per fan first.
/// @param options  see DecimateOptions; target_faces ≥ 1.
/// @param[out] report  counters (optional).
/// @return the coarse mesh, counter-clockwise like the input, every vertex used; at most
///         target_faces faces unless the checks refuse every further collapse.
/// @throws InvalidInput for invalid mesh data (validate_mesh_data()), non-manifold or
///         inconsistently oriented edges, or target_faces < 1.
/// @note O(#F log #F); single-threaded below the size above, allocating about 150 bytes per input
///       face (positions, quadrics, corner lists and the lazy priority queue); above it, that per
///       part at once on every core (TBB), and 16 bytes per input face for the Morton order.
TriangleMesh decimate_mesh(const TriangleMesh& mesh, const DecimateOptions& options, DecimateReport* report = nullptr);

}  // namespace hdm
