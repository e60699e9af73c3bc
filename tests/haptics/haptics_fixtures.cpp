// SPDX-License-Identifier: MIT
#include "haptics/haptics_fixtures.h"

#include "support/test_models.h"

#include <hdm/slab/bake.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace hdm::test {

const SphereFixture& sphere() {
  static const SphereFixture f = [] {
    SphereFixture s;
    BakeOptions o;
    o.slabs = 120;
    o.grid_n = 8;
    s.model = bake_slabs(icosphere(4, 1.0), "icosphere", o);
    s.locator = std::make_unique<SlabLocator>(s.model);
    s.ws.origin = Vec3::Zero();
    s.ws.scale = 10.0;
    s.diag = s.model.source_diagonal;
    return s;
  }();
  return f;
}

const BunnyFixture& paper_bunny() {
  static const BunnyFixture f{baked_bunny(150, 16), SlabLocator(baked_bunny(150, 16)), ExactMeshQuery(bunny()),
                              bounds(bunny()).diagonal()};
  return f;
}

namespace {
SlabModel bake(const TriangleMesh& mesh, const std::string& name, int slabs, int grid_n) {
  BakeOptions o;
  o.slabs = slabs;
  o.grid_n = grid_n;
  return bake_slabs(mesh, name, o);
}
}  // namespace

BakedMesh::BakedMesh(const TriangleMesh& mesh, const std::string& name, int slabs, int grid_n)
    : model(bake(mesh, name, slabs, grid_n)), locator(model), reference(mesh) {}

ProxyParams sphere_params(bool friction) {
  ProxyParams p;
  p.force.stiffness = 1000;
  p.force.damping = 0;
  p.force.max_force = 3.3;
  p.friction_scale = friction ? 1.0 : 0.0;
  return p;
}

SlabModel sphere_with_friction() {
  SlabModel model = sphere().model;
  model.friction_static.assign(model.friction_static.size(), 0.5f);
  model.friction_dynamic.assign(model.friction_dynamic.size(), 0.3f);
  return model;
}

double angle_deg(const Vec3& a, const Vec3& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180 / std::numbers::pi;
}

}  // namespace hdm::test
