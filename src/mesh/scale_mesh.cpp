// SPDX-License-Identifier: MIT
#include <hdm/core/error.h>
#include <hdm/mesh/scale_mesh.h>

#include <cmath>
#include <cstdio>

namespace hdm {

int scale_exponent(double diagonal, const std::string& what) {
  if (!std::isfinite(diagonal) || diagonal < kMinDiagonal || diagonal > kMaxDiagonal) {
    char size[64];
    std::snprintf(size, sizeof size, "%.3g", diagonal);
    throw InvalidInput(what + ": the bounding-box diagonal is " + size +
                       " model units; hdm bakes models whose diagonal is from 1e-30 to 1e30 (the range of "
                       "single-precision sample positions); rescale the mesh");
  }
  return -std::ilogb(diagonal);  // diagonal = m·2^e with m ∈ [1, 2)
}

void scale_mesh(TriangleMesh& mesh, int exponent) noexcept {
  if (exponent == 0) return;
  for (Vec3& v : mesh.vertices)
    for (int i = 0; i < 3; ++i) v[i] = std::ldexp(v[i], exponent);
}

}  // namespace hdm
