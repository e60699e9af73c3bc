// SPDX-License-Identifier: MIT
#pragma once
// Strokes on the bunny for the edit tests: paths on the surface (found with the exact input, not
// the slab model), open-loop tool samples for StrokeEditor, and snapshots of every array an edit
// may change.
#include "support/test_models.h"

#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/edit/stroke_editor.h>

#include <cmath>
#include <cstring>
#include <vector>

namespace hdm::test {

/// A private copy of the default-density bunny bake with its locator; lengths are given in
/// "device millimetres" (the diagonal fitted to 160 mm, as `hdm sculpt` does).
struct BunnyStrokes {
  BunnyStrokes();
  SlabModel model;
  SlabLocator locator;
  double diag = 0, mm = 0;
  /// Points on the input surface and their normals along the straight line from @p a to @p b
  /// (model units), every @p step: each point projected to the closest point of the input.
  void surface_path(const Vec3& a, const Vec3& b, double step, std::vector<Vec3>& points,
                    std::vector<Vec3>& normals) const;
  /// A point on the model's surface near the box point with normalised coordinates @p u (the
  /// closest input point to it).
  Vec3 surface_point(const Vec3& u, Vec3* normal = nullptr) const;
  /// Drives @p editor through one stroke with @p brush: a tool sample every @p dt seconds at the
  /// HIP @p depth below each path point (along the input normal), contacts from the slab query at
  /// that HIP, normal force @p force_n; work() to the end after each sample.
  void stroke(StrokeEditor& editor, const Brush& brush, const std::vector<Vec3>& points,
              const std::vector<Vec3>& normals, double depth, double dt = 1e-3, double force_n = 1.0);
};

/// Every sample's unit normal (sample_normal()), in sample order.
inline std::vector<Vec3f> sample_normals(const SlabModel& m) {
  std::vector<Vec3f> out(static_cast<size_t>(m.samples.count));
  for (int32_t s = 0; s < m.samples.count; ++s) out[size_t(s)] = sample_normal(m, s);
  return out;
}

/// Every array an edit may change, stored and derived.
struct ModelState {
  explicit ModelState(const SlabModel& m)
      : displacement(m.displacement),
        friction_static(m.friction_static.codes()),
        friction_dynamic(m.friction_dynamic.codes()),
        stiffness_scale(m.stiffness_scale.codes()),
        layer_displacement(m.layer_displacement.codes()),
        roughness(m.roughness.codes()),
        colour(m.colour.codes()),
        normals(sample_normals(m)),
        slab_samples(m.slab_samples) {}
  std::vector<Unorm16> displacement;
  std::vector<Half16> friction_static, friction_dynamic;
  std::vector<Unorm16> stiffness_scale, layer_displacement;
  std::vector<uint8_t> roughness;
  std::vector<Srgb8> colour;
  std::vector<Vec3f> normals;
  std::vector<SlabSample> slab_samples;
};

/// Calls @p fn(sample, texel) at every displacement sample's grid point of every slab: the texel
/// there (every m-th texel) lies at the sample's surface point, a position found independently of
/// the texel code. A sample on a slab edge is visited once per slab holding it.
template <class Fn>
void for_each_sample_texel(const SlabModel& model, Fn&& fn) {
  const SampleLayout &S = model.samples, &T = model.texels;
  const int m = model.texel_density, N = T.n;
  for (int slab = 0; slab < model.slab_count(); ++slab)
    for (int j = 0; j <= S.n; ++j)
      for (int i = 0; i + j <= S.n; ++i) {
        const int ti = i * m, tj = j * m;
        fn(S.id(slab, j * (S.n + 1) - j * (j - 1) / 2 + i), T.id(slab, tj * (N + 1) - tj * (tj - 1) / 2 + ti));
      }
}

/// IEC 61966-2-1: a linear channel (clamped to [0,1]) sRGB-encoded, in 8-bit code units (not rounded).
inline double srgb_code(double linear) {
  const double c = linear < 0 ? 0 : linear > 1 ? 1 : linear;
  return 255 * (c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055);
}

/// Names the first array of @p a that differs from @p b bit for bit, or returns "".
std::string first_difference(const ModelState& a, const ModelState& b);

}  // namespace hdm::test
