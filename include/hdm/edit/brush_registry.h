// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// The brush registry: one description per brush (its name, its studio label, the parameters it
/// reads with their valid ranges and defaults, where a stroke puts the tool, and its flood kernel),
/// read by the edit job, the stroke editor, `hdm sculpt`'s scripts, the studio, Python and the
/// benchmarks instead of lists of their own. A brush is its kernel file (src/edit/flood_*.cpp)
/// plus its entry in src/edit/brush_registry.cpp (docs/architecture.md, "How to add a brush").
/// The table is static data: looking a brush up never allocates, so the servo tick may do it.

#include <hdm/edit/brush.h>

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace hdm {

namespace edit::detail {
struct BrushHooks;
}

/// A parameter of hdm::Brush (bit `1 << p` of BrushInfo::params).
enum class BrushParam : uint8_t {
  Radius,           ///< Brush::radius
  Strength,         ///< Brush::strength
  Falloff,          ///< Brush::falloff
  Resilience,       ///< Brush::resilience
  Height,           ///< Brush::height
  Field,            ///< Brush::field
  Colour,           ///< Brush::colour (the Colour field)
  Value,            ///< Brush::value (a scalar field)
  Pressure,         ///< Brush::pressure_force_n
  WearCoefficient,  ///< Brush::wear_coefficient
  Rpm,              ///< Brush::rpm
};

/// Number of BrushParam values.
inline constexpr int brush_param_count = 11;

/// The valid values of one parameter of hdm::Brush: finite and in [lo, hi] ((lo, hi] when
/// `lo_open`); hi may be infinite (no upper bound but finiteness). Colour: each component.
/// Field and Falloff are enumerations: lo = hi = 0, every value of the enumeration is valid.
struct BrushParamRange {
  BrushParam param;  ///< the parameter
  const char* name;  ///< as Python's keyword and error messages spell it (radius, strength, ...)
  const char* unit;  ///< "model units", "N", "" (dimensionless), "linear RGB" or "rpm"
  /// @{ Bounds of the valid values (see the struct).
  double lo, hi;
  /// @}
  bool lo_open;  ///< lo itself is not valid
};

/// Where a stroke puts the tool for each tool position (hdm::StrokeEditor).
enum class ToolPlacement : uint8_t {
  Contact,       ///< the surface contact point: the brush's centre on the surface
  BehindHip,     ///< the sphere's centre at hip + axis·(radius + resilience) (paper §4.1)
  StartSurface,  ///< the sphere whose top stands `height` above the stroke's starting surface
};

/// One registered brush. Its value in BrushTool is its index in brush_registry().
struct BrushInfo {
  BrushTool tool;     ///< what hdm::Brush::tool holds for it
  const char* name;   ///< as scripts, the studio's scripts and Python spell it ("carve")
  const char* label;  ///< the studio's tools panel ("carve")
  /// What it does, one sentence (the studio's tooltip, Python's docstrings); units in hdm::Brush.
  const char* summary;
  uint16_t params;  ///< bit `1 << BrushParam` for each parameter the brush reads
  Falloff falloff;  ///< its default falloff (the studio and Python; scripts: see docs/editing.md)
  /// Where a stroke puts the tool (the sphere's centre or the contact point).
  ToolPlacement placement;
  /// The tool's axis is the normal of the stroke's starting surface (the tool is placed or
  /// oriented along it: carve, add, flatten); otherwise the contact normal.
  bool along_axis;
  const edit::detail::BrushHooks* hooks;  ///< internal: its flood kernel (src/edit/edit_job.h)
  /// True when the brush reads parameter @p p. noexcept, O(1).
  constexpr bool uses(BrushParam p) const noexcept { return (params >> static_cast<int>(p)) & 1u; }
};

/// @brief Every registered brush, in BrushTool order. noexcept, O(1), static storage.
std::span<const BrushInfo> brush_registry() noexcept;

/// @brief The description of @p tool, or nullptr when @p tool is not a registered brush.
/// @note noexcept, O(1), no allocation: the servo tick may call it.
const BrushInfo* find_brush(BrushTool tool) noexcept;

/// @brief The brush named @p name (BrushInfo::name), or nullptr. noexcept, O(#brushes).
const BrushInfo* find_brush(std::string_view name) noexcept;

/// @brief The valid range of parameter @p p. noexcept, O(1).
const BrushParamRange& brush_param_range(BrushParam p) noexcept;

/// @brief The registered names as an error message lists them: "carve, add, ... or paint".
/// @note Allocates the string; O(#brushes).
std::string brush_names();

/// @brief Throws unless every numeric parameter of @p brush lies in its range
/// (brush_param_range()), whether or not its tool reads it, and its tool is registered.
/// @throws InvalidInput "<name> = <value>: must be ..." naming the first parameter out of range
///         (radius, strength, resilience, height, colour, value, pressure_force_n, wear_coefficient,
///         rpm) and the reason; also when a friction or hardness field's value exceeds 65,504 in
///         magnitude (those fields are stored as binary16, SlabModel).
/// @note O(#parameters).
void check_brush(const Brush& brush);

}  // namespace hdm
