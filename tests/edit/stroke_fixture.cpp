// SPDX-License-Identifier: MIT
#include "edit/stroke_fixture.h"

#include <hdm/query/slab_query.h>

namespace hdm::test {
namespace {

const ExactMeshQuery& exact_bunny() {
  static const ExactMeshQuery q(bunny());
  return q;
}

template <class T>
bool same(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

}  // namespace

BunnyStrokes::BunnyStrokes() : model(baked_bunny(0, 16)), locator(model) {
  diag = model.source_diagonal;
  mm = diag / 160.0;
}

Vec3 BunnyStrokes::surface_point(const Vec3& u, Vec3* normal) const {
  const Aabb box = bounds(bunny());
  const Vec3 p = box.min + u.cwiseProduct(box.max - box.min);
  const ClosestPoint c = exact_bunny().closest_point(p);
  if (normal) {
    const Tri& f = bunny().faces[c.face];
    const Vec3 &a = bunny().vertices[f[0]], &b = bunny().vertices[f[1]], &d = bunny().vertices[f[2]];
    *normal = (b - a).cross(d - a).normalized();
  }
  return c.point;
}

void BunnyStrokes::surface_path(const Vec3& a, const Vec3& b, double step, std::vector<Vec3>& points,
                                std::vector<Vec3>& normals) const {
  points.clear(), normals.clear();
  const int n = std::max(1, static_cast<int>((b - a).norm() / step));
  QueryCache cache;
  for (int k = 0; k <= n; ++k) {
    const Vec3 x = a + (b - a) * (double(k) / n);
    const Vec3 p = exact_bunny().closest_point(x).point;
    // The slab model's own smooth normal at the point (the input's face normals are noisy).
    const Contact c = query(model, locator, p, cache);
    points.push_back(p);
    normals.push_back(c.in_shell() ? c.normal : Vec3::UnitZ());
  }
}

void BunnyStrokes::stroke(StrokeEditor& editor, const Brush& brush, const std::vector<Vec3>& points,
                          const std::vector<Vec3>& normals, double depth, double dt, double force_n) {
  editor.begin_stroke(brush);
  QueryCache cache;
  for (size_t k = 0; k < points.size(); ++k) {
    ToolSample t;
    t.hip = points[k] - depth * normals[k];
    t.contact = query(model, locator, t.hip, cache);
    t.normal_force_n = force_n;
    t.units_per_metre = 1000 * mm;  // the device millimetres of the fixture
    t.time_s = dt * double(k);
    editor.add_sample(model, t);
    editor.work(model, INT64_MAX);
  }
  editor.end_stroke();
  editor.work(model, INT64_MAX);
}

std::string first_difference(const ModelState& a, const ModelState& b) {
  if (!same(a.displacement, b.displacement)) return "displacement";
  if (!same(a.friction_static, b.friction_static)) return "friction_static";
  if (!same(a.friction_dynamic, b.friction_dynamic)) return "friction_dynamic";
  if (!same(a.stiffness_scale, b.stiffness_scale)) return "stiffness_scale";
  if (!same(a.layer_displacement, b.layer_displacement)) return "layer_displacement";
  if (!same(a.roughness, b.roughness)) return "roughness";
  if (!same(a.colour, b.colour)) return "colour";
  if (!same(a.normals, b.normals)) return "normals";
  if (!same(a.slab_samples, b.slab_samples)) return "slab_samples";
  return "";
}

}  // namespace hdm::test
