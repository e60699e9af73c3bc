// SPDX-License-Identifier: MIT
#pragma once
// Internals of the tool scenarios (tool_scenarios.h): the baked block they share and the rigid
// tool's scenario, which has its own file.
#include <hdm/harness/tool_scenarios.h>
#include <hdm/harness/voxel_surface.h>
#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/query/slab_locator.h>
#include <hdm/slab/bake.h>

#include <functional>

namespace hdm::harness::detail {

inline constexpr double kToolScale = 10;  // model units per metre: the 2-unit block is 0.2 m wide

// The block [-1,1]² × [-1,0] from 20 × 20 × 10 cubes of 0.1, less the cells @p solid leaves out,
// baked into 500 slabs with @p grid_n intervals per slab edge, with exact queries on its own mesh.
struct Block {
  explicit Block(const std::function<bool(int, int, int)>& solid, int grid_n = 8)
      : mesh(voxel_surface(20, 20, 10, 0.1, Vec3(-1, -1, -1), solid)),
        model(bake(mesh, grid_n)),
        locator(model),
        reference(mesh) {}
  static SlabModel bake(const TriangleMesh& m, int grid_n) {
    BakeOptions o;
    o.slabs = 500;
    o.grid_n = grid_n;
    return bake_slabs(m, "block", o);
  }
  TriangleMesh mesh;
  SlabModel model;
  SlabLocator locator;  // after model: built from it
  ExactMeshQuery reference;
};

// Work of the wrench held over the last period on the handle's motion in that period, split into
// what it returned to the hand (positive work) and what it absorbed: the energy ratio of the
// point scenarios (scenarios.cpp), with the torque's work on the handle's turn added.
struct EnergyTally {
  Vec3 x_prev = Vec3::Zero(), f_prev = Vec3::Zero(), t_prev = Vec3::Zero();
  double returned = 0, absorbed = 0;
  bool started = false;
  // @p x handle position [m], @p turn its rotation vector over the period [rad] (zero for a
  // handle that only moves), @p f and @p t the force [N] and torque [N·m] sent this tick.
  void add(const Vec3& x, const Vec3& turn, const Vec3& f, const Vec3& t) {
    if (started) {
      const double w = f_prev.dot(x - x_prev) + t_prev.dot(turn);
      (w > 0 ? returned : absorbed) += std::abs(w);
    }
    started = true, x_prev = x, f_prev = f, t_prev = t;
  }
  double ratio() const { return absorbed > 0 ? returned / absorbed : 0; }
};

// ToolScenario::ShaftEdge (shaft_edge_scenario.cpp).
ToolScenarioReport run_shaft_edge(const ToolScenarioOptions& options);
// ToolScenario::DrillLayers (drill_layers_scenario.cpp).
ToolScenarioReport run_drill_layers(const ToolScenarioOptions& options);

}  // namespace hdm::harness::detail
