// SPDX-License-Identifier: MIT
#pragma once
// Internal to bake_to_tolerance(): where the next round's coarse mesh must be finer.

#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/slab/slab_model.h>

#include <cstdint>
#include <vector>

namespace hdm::analysis::detail {

// Local refinement. The faulty slabs (@p faulty: ids of overlapping slabs of @p model; and the
// slabs nearest @p far_points, where the reconstruction misses the distance bound; all on the
// shell's mid-surface) ask for smaller slabs there: each vertex of the coarse source @p source
// (the mesh decimated into slabs) within half a faulty slab's longest edge of it gets at most
// that half edge in @p max_edge (#V of source, +inf where free; a smaller value from an earlier
// round stays).
// O(#V log #S) closest-point queries (parallel), one BVH over the #S mid-surface triangles.
void tighten_edge_caps(const SlabModel& model, const TriangleMesh& source, const std::vector<int32_t>& faulty,
                       const std::vector<Vec3>& far_points, std::vector<double>& max_edge);

}  // namespace hdm::analysis::detail
