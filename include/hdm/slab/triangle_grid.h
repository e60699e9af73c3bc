// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Index arithmetic of a triangular grid with `n` intervals per edge (paper §2, Fig. 5c).
///
/// Grid point (i, j) has i, j >= 0 and i + j <= n, barycentrics wT = i/n, wS = j/n,
/// wR = 1 - (i+j)/n: R is (0,0), T is (n,0), S is (0,n). Points are packed row by row
/// (row j holds n+1-j points). Grid triangles: for each cell (i, j) with i + j <= n-1 an "up"
/// triangle (i,j),(i,j+1),(i+1,j) and, where i + j <= n-2, a "down" triangle
/// (i+1,j),(i,j+1),(i+1,j+1); both counter-clockwise seen from outside (docs/design.md#sample-grid).
/// Haptics, normals, rendering and export all use this one split.

#include <cstdint>

namespace hdm::grid {

/// Number of grid points of a triangle with @p n intervals per edge: (n+1)(n+2)/2.
constexpr int point_count(int n) noexcept { return (n + 1) * (n + 2) / 2; }

/// Packed index of grid point (i, j). Precondition: i, j >= 0, i + j <= n. noexcept, O(1).
constexpr int index(int n, int i, int j) noexcept { return j * (n + 1) - j * (j - 1) / 2 + i; }

/// Number of grid triangles: n².
constexpr int triangle_count(int n) noexcept { return n * n; }

}  // namespace hdm::grid
