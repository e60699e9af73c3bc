// SPDX-License-Identifier: MIT
#pragma once
// Internal, for the bake's translation units: the search for the direction that sees a set of unit
// normals best, shared by the decimation's fold test and the bake's ray directions.

#include <hdm/core/types.h>

#include <vector>

namespace hdm::mesh::detail {

// Improves @p best_value, the smallest dot product of a unit direction with @p normals, towards
// the max-min optimum (the centre of the smallest spherical cap holding them). The optimum is fixed
// by one, two or three active normals: every normal, every pair's bisector and, up to 24 normals,
// every triple's circumcentre are tried. @p best_direction (may be null) gets the direction of an
// improvement. O(k^3) dot products for k <= 24 normals, O(k^2) candidates above, each ruled out
// by the normal that ruled out the last one in most cases (one product, no root): the same result,
// bit for bit, as checking every candidate against every normal in order.
void improve_max_min(const std::vector<Vec3>& normals, double& best_value, Vec3* best_direction);

}  // namespace hdm::mesh::detail
