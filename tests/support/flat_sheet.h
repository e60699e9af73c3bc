// SPDX-License-Identifier: MIT
#pragma once
// A flat slab model in millimetres for the drill's tests, and the volume removed from it measured
// independently of any kernel: the displaced surface's grid triangles, each its area times the mean
// drop of its corners (exact for the piecewise-linear surface over vertical projection lines).

#include <hdm/slab/slab_model.h>

#include <vector>

namespace hdm::test {

inline constexpr int kSheetQuads = 4;        ///< quads per side of the sheet
inline constexpr double kSheetHalf = 10;     ///< the sheet spans [-10, 10]² [mm]
inline constexpr double kSheetUnits = 1000;  ///< model units per metre (millimetres)

/// The square split into kSheetQuads² quads (two slabs each, CCW seen from +z), inner face at
/// z = -1, outer at z = +1, grid n = 16 (sample spacing 0.3125 mm), every δ = 0.5 (stored as its
/// nearest unorm16 code, 32768/65535): the surface is the plane z = sheet_surface_z().
SlabModel flat_sheet();

/// Height of flat_sheet()'s surface [mm]: -1 + 2·δ for δ = 0.5 as stored (1.5e-5 above z = 0).
inline double sheet_surface_z() { return -1.0 + 2.0 * double(float(Unorm16(0.5f))); }

/// The slab and barycentrics (wR, wS, wT) of the sheet's point (x, y).
void locate_on_sheet(double x, double y, int32_t& slab, Vec3& bary);

/// Volume between the sheet's displaced surface points @p before (displaced_surface()) and its
/// surface now [mm³]: each grid triangle's area times the mean drop of its three corners.
double removed_volume(const SlabModel& m, const std::vector<Vec3>& before);

}  // namespace hdm::test
