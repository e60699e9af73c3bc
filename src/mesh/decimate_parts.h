// SPDX-License-Identifier: MIT
#pragma once
// Internal to decimate_mesh(): the decimation of a pinch-free copy of a mesh, and the passes of a
// large input's decimation made in spatial parts at once, before the whole's.

#include <hdm/mesh/decimate_mesh.h>

#include <cstdint>
#include <vector>

namespace hdm::mesh::detail {

// decimate_mesh() on a validated @p mesh: vertices shared by several fans split, the collapse
// queue run, then (with @p clean) the stars no direction sees cleaned. @p kept (optional) gets,
// per vertex of the result, the vertex of @p mesh it is (a split copy: the vertex it was split from),
// and @p max_edge (optional, with options.max_edge) the longest edge a later collapse may make there
// (the least max_edge of the vertices merged into it). No collapse touches a vertex with @p frozen 1
// or its edges (Simplifier::freeze(); empty: none).
TriangleMesh decimate_pinch_free(const TriangleMesh& mesh, const DecimateOptions& options, bool clean,
                                 DecimateReport* report, std::vector<int32_t>* kept,
                                 std::vector<uint8_t> frozen = {}, std::vector<double>* max_edge = nullptr);

// Whether decimate_mesh() decimates @p mesh in parts first (decimate_in_parts()): a large input
// (at least kLargeFaces faces, 64 times the target or more).
bool decimate_in_parts_first(const TriangleMesh& mesh, const DecimateOptions& options);

// Faces from which an input is large.
inline constexpr int64_t kLargeFaces = 1 << 20;
// One pass of decimate_in_parts(): parts of about `part_faces` faces, each decimated to its share
// of `keep` times the target.
struct PartsPass {
  int64_t part_faces;
  double keep;
};
// The passes of a large input's decimation before the whole's. Small parts first: a part's
// collapse queue, about 20 bytes per entry and three entries per face, then fits a cache; their
// frozen borders, where they meet, are then decimated in a second pass over parts cut anew (the
// joined mesh's own Morton order), so the whole's one queue has little left. Armadillo subdivided
// to 12.6 M triangles, to 32,768 faces (a probe timing decimate_in_parts() and the whole): one
// pass of 2¹⁷-face parts to 16 times the target left 1.25 M faces, 15.9 s + 5.8 s for the whole;
// these two passes leave 451,000 faces, 13.2 s + 2.2 s + 1.3 s, and the coarse mesh is as close to
// the input (largest input-vertex distance 0.110 % of the diagonal against 0.114 %, RMS 0.0162 %
// against 0.0172 %).
inline constexpr PartsPass kPartsPasses[] = {{1 << 15, 16.0}, {1 << 16, 4.0}};

// One pass of a large input's decimation: the faces cut into parts of about pass.part_faces faces
// along a Morton curve of their centroids, each part decimated on its own (in parallel, TBB) to its
// share of pass.keep times options.target_faces, with the vertices two parts share, and every edge
// to them, left as they are (frozen), so the parts still join. The result has the input's topology
// (each part's collapses keep it, and none touches where parts meet). Why: one queue over millions
// of edges is slow and cannot be shared between threads; a part's is small and its own (armadillo
// subdivided to 12.6 M triangles: see docs/performance.md). With options.max_edge, each part's
// collapses keep to it, and @p max_edge gets the value for each vertex of the result that later
// collapses must keep to (the least of the input vertices merged into it). @p report gets the
// parts' collapses and largest cost.
TriangleMesh decimate_in_parts(const TriangleMesh& mesh, const DecimateOptions& options, const PartsPass& pass,
                               DecimateReport* report, std::vector<double>* max_edge);

}  // namespace hdm::mesh::detail
