// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Brushes: the tools a sculptor strokes over a slab model (carve, add, smooth, flatten, paint, drill),
/// each with a radius, a strength and a falloff, and the field a paint brush writes.
/// How each tool acts is documented on BrushTool; the stroke semantics (a stroke is the swept
/// tool, applied once per stroke whatever the servo rate) in hdm/edit/stroke_editor.h and
/// docs/editing.md.

#include <hdm/core/types.h>

#include <cstdint>
#include <string>

namespace hdm {

/// What a brush does. The value is the brush's index in hdm::brush_registry(), where each brush
/// is described (name, parameters and their ranges, kernel: hdm/edit/brush_registry.h).
enum class BrushTool : uint8_t {
  /// Removes material inside the swept sphere of radius r centred at HIP + n·(r + resilience)
  /// (paper §4.1; a capsule between consecutive tool positions): the surface is cut to the
  /// tool's entry point on each projection line. Strength 1 with Falloff::Constant is the exact
  /// boolean difference; lower strength or another falloff cuts a fraction s·f(x) of the way
  /// from the stroke's starting surface to the tool. Never raises the surface.
  Carve,
  /// Adds material inside the swept sphere of radius r whose top stands `height` above the
  /// stroke's starting surface at the contact (paper §4.2's deposit as a boolean union, so a
  /// stroke is a ridge of that height however long the tool dwells; a second stroke adds on top).
  /// Never lowers the surface; no overhangs (δ ≤ 1, and a tool floating above a column adds nothing).
  Add,
  /// Relaxes each displacement towards the mean of its grid neighbours' at the rate
  /// strength·pressure·f(x)·20 s⁻¹ (so strength 1 at full pressure relaxes 63 % in 50 ms of contact).
  Smooth,
  /// Moves each displacement towards the tool's plane (through the surface contact point, normal
  /// to the contact normal) at the same rate as Smooth.
  Flatten,
  /// Blends the chosen field towards the brush value with intensity k = pressure·strength·f(x)
  /// (paper §5), once per stroke: a texel or sample ends at base + k_max·(value − base), k_max the
  /// largest intensity the stroke reached there.
  Paint,
  /// Removes material by Archard's wear law (Archard 1953, "Contact and rubbing of flat surfaces",
  /// J. Appl. Phys. 24(8), 981-988): per sweep the volume V = K·F_n·v_s·Δt / H, with K the wear
  /// coefficient (Brush::wear_coefficient), F_n the contact's normal force [N]
  /// (BrushSweep::normal_force_n), v_s = ω·r the burr's surface speed [m/s] (ω from Brush::rpm
  /// times strength, the pedal; r the radius in metres), Δt the sweep's contact time [s]
  /// (BrushSweep::dt) and H the hardness [Pa] (SlabModel::hardness or the under-layer's,
  /// 1 HV = 9.80665 MPa). The force is spread over the samples within the radius of the contact's
  /// path in proportion to falloff × area, and each sample's share of V, at its own hardness,
  /// lowers it along its projection line. Never raises the surface; nothing without force or
  /// time. Units: BrushSweep::units_per_metre (docs/haptics.md, "Drilling").
  Drill,
};

/// Weight of a brush at normalised distance x = d / r from its centre (or its swept path).
enum class Falloff : uint8_t {
  Constant,  ///< 1 inside the radius: the exact boolean for carve and add (their default)
  Linear,    ///< 1 − x: the paper's cone (paint, §5)
  Smooth,    ///< 1 − 3x² + 2x³ (smoothstep): no crease at the rim
};

/// The field a Paint brush writes.
enum class BrushField : uint8_t {
  Colour,           ///< per-texel linear RGB (SlabModel::colour)
  Roughness,        ///< per-texel rendering roughness in [0,1] (SlabModel::roughness)
  FrictionStatic,   ///< per-sample μs (SlabModel::friction_static)
  FrictionDynamic,  ///< per-sample μd (SlabModel::friction_dynamic)
  Stiffness,        ///< per-sample stiffness scale in [0,1] (SlabModel::stiffness_scale)
  /// Thickness of the top material over the under-layer [model units]: the layer's top is put
  /// that far below the stroke's starting surface along each projection line
  /// (SlabModel::layer_displacement).
  LayerThickness,
  /// Per-sample Vickers hardness [HV] (SlabModel::hardness), painted values at least 1 HV.
  Hardness,
};

/// A brush. Lengths in model units (hdm::Workspace::scale converts device metres).
struct Brush {
  BrushTool tool = BrushTool::Carve;    ///< what it does
  double radius = 0;                    ///< tool radius [model units], > 0
  double strength = 1;                  ///< in [0,1]; see BrushTool for its meaning per tool
  Falloff falloff = Falloff::Constant;  ///< weight across the radius
  double resilience = 0;                ///< carve: resilient band k [model units] (paper §4.1), >= 0
  double height = 0;  ///< add: height of the added ridge above the stroke's start surface [model units]
  BrushField field = BrushField::Colour;  ///< paint: the field written
  Vec3f colour{0.8f, 0.1f, 0.1f};         ///< paint Colour: linear RGB
  float value = 0;                ///< paint of a scalar field: the value painted (layer thickness in model units)
  double pressure_force_n = 1.0;  ///< normal force [N] that gives full pressure (paint, smooth, flatten);
                                  ///< pressure ramps from 0 at 10 % of it (paint_pressure)
  /// drill: Archard's dimensionless wear coefficient K, in (0, 1] (default 0.01)
  double wear_coefficient = 0.01;
  /// drill: the burr's speed [revolutions per minute], in (0, 10⁶] (default 200,000: a dental
  /// high-speed handpiece; bone drills turn at 1,000-60,000); surface speed ω·r with r = radius
  double rpm = 200000;
};

/// @brief Weight of falloff @p f at normalised distance @p x (clamped to [0,1]); 0 for x >= 1.
/// @note noexcept, O(1).
inline double falloff_weight(Falloff f, double x) noexcept {
  if (!(x < 1)) return 0.0;
  if (x < 0) x = 0;
  switch (f) {
    case Falloff::Linear:
      return 1 - x;
    case Falloff::Smooth:
      return 1 - x * x * (3 - 2 * x);
    default:
      return 1.0;
  }
}

/// @brief Parses a tool name: a registered brush's name (carve, add, smooth, flatten, paint, drill).
/// @throws InvalidInput naming @p name and listing the registered names otherwise.
BrushTool parse_brush_tool(const std::string& name);
/// @brief Parses a falloff name: constant, linear, smooth. @throws InvalidInput otherwise.
Falloff parse_falloff(const std::string& name);
/// @brief Parses a field name: colour, roughness, friction_static, friction_dynamic, stiffness,
/// layer_thickness, hardness. @throws InvalidInput otherwise.
BrushField parse_brush_field(const std::string& name);
/// Name of @p tool as parse_brush_tool() reads it ("?" for an unregistered value).
const char* brush_tool_name(BrushTool tool) noexcept;

}  // namespace hdm
