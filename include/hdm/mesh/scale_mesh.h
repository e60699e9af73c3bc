// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Scale normalisation by a power of two. Multiplying binary floating-point coordinates by 2^k
/// only shifts their exponents, so it is exact: a mesh scaled by any power of ten bakes, after
/// normalisation, to the same slabs up to the input's own rounding, and every tolerance of the
/// bake and the check works at one size (docs/reliability.md#scale).

#include <hdm/mesh/triangle_mesh.h>

#include <string>

namespace hdm {

/// Smallest bounding-box diagonal accepted [model units]: below it the model's single-precision
/// caches (the normals' area-weighted sums, over edges 1e-4 of the diagonal long) would leave float's normal range.
inline constexpr double kMinDiagonal = 1e-30;
/// Largest bounding-box diagonal accepted [model units] (float's range, with room for the shell).
inline constexpr double kMaxDiagonal = 1e30;

/// @brief The power-of-two exponent k that brings a bounding-box diagonal @p diagonal into [1, 2):
/// 2^k · diagonal ∈ [1, 2).
/// @param diagonal bounding-box diagonal [model units].
/// @param what names the input in the error message (a file name).
/// @throws InvalidInput naming @p what and the scale when @p diagonal is not finite or lies
///         outside [kMinDiagonal, kMaxDiagonal] (a mesh of one point included).
/// @note O(1); never allocates except for the message.
int scale_exponent(double diagonal, const std::string& what);

/// @brief Multiplies every vertex of @p mesh by 2^@p exponent, exactly (std::ldexp).
/// @param mesh     the mesh, changed in place [model units].
/// @param exponent power of two; 0 leaves the mesh as it is.
/// @note O(#V); no allocation. Exact while the results stay normal doubles, which
///       scale_exponent()'s range guarantees for a normalising exponent and its inverse.
void scale_mesh(TriangleMesh& mesh, int exponent) noexcept;

}  // namespace hdm
